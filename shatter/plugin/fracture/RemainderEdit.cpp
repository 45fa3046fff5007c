#include <shatter/plugin/fracture/RemainderEdit.h>

#include <algorithm>

namespace shatter::fracture {

geometry::MassProperties withoutPart(const geometry::MassProperties& whole, const geometry::MassProperties& part) {
    geometry::MassProperties rest;
    rest.volume = whole.volume - part.volume;
    rest.mass = whole.mass - part.mass;
    if (rest.mass <= 0.0) return rest;
    rest.centerOfMass = (whole.mass * whole.centerOfMass - part.mass * part.centerOfMass) / rest.mass;
    // Inertia about the whole's centre is the sum of both parts' (parallel axes); take the
    // part's out and move what is left to the rest's own centre.
    auto shift = [](double m, const Eigen::Vector3d& d) {
        return Eigen::Matrix3d(m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
    };
    const Eigen::Matrix3d restAboutWhole =
        whole.inertia - part.inertia - shift(part.mass, part.centerOfMass - whole.centerOfMass);
    rest.inertia = restAboutWhole - shift(rest.mass, rest.centerOfMass - whole.centerOfMass);
    return rest;
}

void applyFaceEdit(geometry::VisualMesh& visual, const RemainderEdit& edit) {
    const bool hadCracks = !visual.crackFace.empty();
    if (hadCracks) visual.crackFace.resize(visual.faces.size(), false);
    // The faces between two dropped ones move down as a block (droppedFaces is ascending).
    size_t kept = edit.droppedFaces.empty() ? visual.faces.size() : size_t(edit.droppedFaces.front());
    for (size_t k = 0; k < edit.droppedFaces.size(); ++k) {
        const size_t begin = size_t(edit.droppedFaces[k]) + 1;
        const size_t end = k + 1 < edit.droppedFaces.size() ? size_t(edit.droppedFaces[k + 1]) : visual.faces.size();
        std::move(visual.faces.begin() + long(begin), visual.faces.begin() + long(end), visual.faces.begin() + long(kept));
        if (hadCracks)
            std::copy(visual.crackFace.begin() + long(begin), visual.crackFace.begin() + long(end),
                      visual.crackFace.begin() + long(kept));
        kept += end - begin;
    }
    visual.faces.resize(kept);
    visual.faces.insert(visual.faces.end(), edit.faces.begin(), edit.faces.end());
    // "Empty when the mesh has no crack face": a mesh without any gains them only from the
    // edit, so only the edit's flags are searched (not bit by bit over the whole mesh).
    if (!hadCracks && std::find(edit.crack.begin(), edit.crack.end(), true) == edit.crack.end()) return;
    visual.crackFace.resize(kept, false);
    visual.crackFace.insert(visual.crackFace.end(), edit.crack.begin(), edit.crack.end());
}

namespace {

// applyRemainderEdit, but for the added pieces. `swapCarriers`: ascending primitives whose ids
// may change, or null to look at every kept primitive's ids.
void closeUp(geometry::PhysicalMesh& body, const RemainderEdit& edit, const std::vector<int>* swapCarriers) {
    const int before = int(body.primitives.size());
    // Where each primitive goes (-1: removed); the others close up in order.
    std::vector<int> to(size_t(before), 0);
    for (int i : edit.removed) to[size_t(i)] = -1;
    for (int i : edit.lostSourceFace) body.sourceFace[size_t(i)] = -1;
    // Where each face goes (-1: dropped); source faces follow their face.
    std::vector<int> faceTo(body.visual.faces.size(), 0);
    for (int f : edit.droppedFaces) faceTo[size_t(f)] = -1;
    int keptFaces = 0;
    for (int& f : faceTo) f = f < 0 ? -1 : keptFaces++;

    // Ids to exchange (identity elsewhere): only primitives carrying one are copied.
    std::vector<int> swapTo(size_t(edit.globalIdCount), -1);
    for (const auto& [a, b] : edit.idSwaps) {
        swapTo[size_t(a)] = b;
        swapTo[size_t(b)] = a;
    }
    int kept = 0;
    size_t carrier = 0; // the first of swapCarriers not below i
    for (int i = 0; i < before; ++i) {
        if (to[size_t(i)] < 0) continue;
        to[size_t(i)] = kept;
        auto& p = body.primitives[size_t(i)];
        bool mayCarry = !edit.idSwaps.empty();
        if (mayCarry && swapCarriers) {
            while (carrier < swapCarriers->size() && (*swapCarriers)[carrier] < i) ++carrier;
            mayCarry = carrier < swapCarriers->size() && (*swapCarriers)[carrier] == i;
        }
        if (mayCarry) {
            const auto& ids = p.globalIds();
            if (std::any_of(ids.begin(), ids.end(), [&](int id) { return swapTo[size_t(id)] >= 0; })) {
                std::vector<int> swapped(ids);
                for (int& id : swapped)
                    if (swapTo[size_t(id)] >= 0) id = swapTo[size_t(id)];
                p.setGlobalIds(std::move(swapped));
            }
        }
        const int source = body.sourceFace[size_t(i)];
        body.sourceFace[size_t(kept)] = source < 0 ? -1 : faceTo[size_t(source)];
        if (kept != i) body.primitives[size_t(kept)] = std::move(p);
        ++kept;
    }
    body.primitives.resize(size_t(kept));
    body.sourceFace.resize(size_t(kept));

    // Connections of two kept primitives, renumbered, in their order: one pass.
    size_t keptConnections = 0;
    for (const auto& [a, b] : body.connections) {
        const int ta = to[size_t(a)], tb = to[size_t(b)];
        if (ta >= 0 && tb >= 0) body.connections[keptConnections++] = {ta, tb};
    }
    body.connections.resize(keptConnections);
    body.connections.insert(body.connections.end(), edit.connections.begin(), edit.connections.end());

    applyFaceEdit(body.visual, edit);
    auto& visual = body.visual;
    visual.positions.insert(visual.positions.end(), edit.newVisualPositions.begin(), edit.newVisualPositions.end());
    body.globalIdCount = edit.globalIdCount;
    body.mass = edit.mass;
}

} // namespace

void applyRemainderEdit(geometry::PhysicalMesh& body, const RemainderEdit& edit) {
    closeUp(body, edit, nullptr);
    body.primitives.insert(body.primitives.end(), edit.added.begin(), edit.added.end());
    body.sourceFace.resize(body.primitives.size(), -1);
}

void applyRemainderEdit(geometry::PhysicalMesh& body, RemainderEdit&& edit, const std::vector<int>& swapCarriers) {
    closeUp(body, edit, &swapCarriers);
    for (auto& p : edit.added) body.primitives.push_back(std::move(p));
    edit.added.clear();
    body.sourceFace.resize(body.primitives.size(), -1);
}

std::vector<char> swappedIds(const RemainderEdit& edit) {
    std::vector<char> swapped(size_t(edit.globalIdCount), 0);
    for (const auto& [a, b] : edit.idSwaps) swapped[size_t(a)] = swapped[size_t(b)] = 1;
    return swapped;
}

} // namespace shatter::fracture
