#include "demos/runner/GltfWriter.h"

#include "demos/runner/BodyColour.h"
#include "demos/runner/FrameWriter.h"
#include "demos/runner/PolygonTriangles.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

namespace shatter::demo {

namespace {

// glTF colour factors are linear; ours are sRGB like the pictures.
double linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

class ModelBuilder {
public:
    explicit ModelBuilder(double fps) : fps_(fps) {
        model_.asset.version = "2.0";
        model_.asset.generator = "Shatter demo runner (tinygltf)";
        model_.buffers.emplace_back();
        model_.scenes.emplace_back();
        model_.defaultScene = 0;
        animation_.name = "run";
    }

    void addTrack(const BodyTrack& track, int frameCount);

    tinygltf::Model finish() {
        if (!animation_.channels.empty()) model_.animations.push_back(std::move(animation_));
        return std::move(model_);
    }

private:
    // Appends raw bytes as a buffer view of their own (4-byte aligned) and returns its index.
    int view(const void* bytes, size_t size, int target) {
        auto& data = model_.buffers[0].data;
        while (data.size() % 4) data.push_back(0);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = data.size();
        v.byteLength = size;
        v.target = target;
        data.insert(data.end(), static_cast<const unsigned char*>(bytes), static_cast<const unsigned char*>(bytes) + size);
        model_.bufferViews.push_back(v);
        return int(model_.bufferViews.size()) - 1;
    }

    template <class T>
    int accessor(const std::vector<T>& values, int componentType, int type, int components, int target,
                 bool withBounds) {
        tinygltf::Accessor a;
        a.bufferView = view(values.data(), values.size() * sizeof(T), target);
        a.byteOffset = 0;
        a.componentType = componentType;
        a.type = type;
        a.count = values.size() / size_t(components);
        if (withBounds) {
            a.minValues.assign(size_t(components), INFINITY);
            a.maxValues.assign(size_t(components), -INFINITY);
            for (size_t i = 0; i < values.size(); ++i) {
                a.minValues[i % size_t(components)] = std::min(a.minValues[i % size_t(components)], double(values[i]));
                a.maxValues[i % size_t(components)] = std::max(a.maxValues[i % size_t(components)], double(values[i]));
            }
        }
        model_.accessors.push_back(std::move(a));
        return int(model_.accessors.size()) - 1;
    }

    int floats(const std::vector<float>& v, int type, int components, bool bounds = false) {
        return accessor(v, TINYGLTF_COMPONENT_TYPE_FLOAT, type, components, 0, bounds);
    }

    int material(const std::string& key, Rgb colour, double roughness) {
        const auto found = materials_.find(key);
        if (found != materials_.end()) return found->second;
        tinygltf::Material m;
        m.name = key;
        m.doubleSided = true; // open surfaces (a door panel, a torn sheet) are seen from both sides
        m.pbrMetallicRoughness.baseColorFactor = {linear(colour.r), linear(colour.g), linear(colour.b), 1.0};
        m.pbrMetallicRoughness.metallicFactor = 0.0;
        m.pbrMetallicRoughness.roughnessFactor = roughness;
        model_.materials.push_back(std::move(m));
        return materials_[key] = int(model_.materials.size()) - 1;
    }

    // The mesh of one shape: shared positions, one primitive for the body's faces and one for
    // crack faces. No normals: glTF viewers then shade flat, as the pictures do. -1 when the
    // shape has no face left.
    int mesh(const std::string& name, const geometry::VisualMesh& shape, const std::function<int()>& bodyMaterial);

    // Time of every frame in [first, last], one accessor per range.
    int times(int first, int last) {
        const auto key = std::pair(first, last);
        const auto found = times_.find(key);
        if (found != times_.end()) return found->second;
        std::vector<float> t;
        for (int f = first; f <= last; ++f) t.push_back(float(f / fps_));
        return times_[key] = floats(t, TINYGLTF_TYPE_SCALAR, 1, true);
    }

    void channel(int node, const char* path, int input, int output, const char* interpolation) {
        tinygltf::AnimationSampler s;
        s.input = input;
        s.output = output;
        s.interpolation = interpolation;
        animation_.samplers.push_back(s);
        tinygltf::AnimationChannel c;
        c.sampler = int(animation_.samplers.size()) - 1;
        c.target_node = node;
        c.target_path = path;
        animation_.channels.push_back(c);
    }

    // A STEP scale channel showing the node (1) in the frames `shown` says and hiding it (0)
    // in the others; keys only where that changes.
    void visibility(int node, int frameCount, const std::function<bool(int)>& shown) {
        std::vector<float> t, s;
        for (int f = 1; f <= frameCount; ++f) {
            const bool v = shown(f);
            if (f == 1 || v != (s.back() > 0)) {
                t.push_back(float(f / fps_));
                for (int k = 0; k < 3; ++k) s.push_back(v ? 1.0f : 0.0f);
            }
        }
        if (t.size() < 2) return; // never changes: the node's own scale says it
        channel(node, "scale", floats(t, TINYGLTF_TYPE_SCALAR, 1, true), floats(s, TINYGLTF_TYPE_VEC3, 3), "STEP");
    }

    int node(tinygltf::Node n) {
        model_.nodes.push_back(std::move(n));
        return int(model_.nodes.size()) - 1;
    }

    double fps_;
    tinygltf::Model model_;
    tinygltf::Animation animation_;
    std::map<std::string, int> materials_;
    std::map<std::pair<int, int>, int> times_;
};

int ModelBuilder::mesh(const std::string& name, const geometry::VisualMesh& shape, const std::function<int()>& bodyMaterial) {
    std::vector<std::uint32_t> body, crack;
    std::vector<Eigen::Vector3d> polygon;
    for (size_t f = 0; f < shape.faces.size(); ++f) {
        polygon.clear();
        for (int v : shape.faces[f]) polygon.push_back(shape.positions[size_t(v)]);
        auto& out = shape.isCrackFace(f) ? crack : body;
        for (const auto& t : polygonTriangles(polygon))
            for (int k : t) out.push_back(std::uint32_t(shape.faces[f][size_t(k)]));
    }
    if (body.empty() && crack.empty()) return -1;
    std::vector<float> positions;
    for (const auto& p : shape.positions)
        for (int k = 0; k < 3; ++k) positions.push_back(float(p[k]));
    const int position = accessor(positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3,
                                  TINYGLTF_TARGET_ARRAY_BUFFER, true);
    tinygltf::Mesh m;
    m.name = name;
    // Materials are made on first use: a validator flags unused ones.
    auto primitive = [&](const std::vector<std::uint32_t>& indices, const std::function<int()>& materialIndex) {
        if (indices.empty()) return;
        tinygltf::Primitive p;
        p.attributes["POSITION"] = position;
        p.material = materialIndex();
        p.mode = TINYGLTF_MODE_TRIANGLES;
        if (shape.positions.size() <= 65535) {
            const std::vector<std::uint16_t> small(indices.begin(), indices.end());
            p.indices = accessor(small, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, 1,
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
        } else {
            p.indices = accessor(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 1,
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
        }
        m.primitives.push_back(std::move(p));
    };
    primitive(body, bodyMaterial);
    primitive(crack, [&] { return material("crack", crackColour(), 1.0); });
    model_.meshes.push_back(std::move(m));
    return int(model_.meshes.size()) - 1;
}

void ModelBuilder::addTrack(const BodyTrack& track, int frameCount) {
    const auto bodyMaterial = [&] {
        return track.ground ? material("ground", {0.75, 0.77, 0.80}, 1.0) : material(track.name, bodyColour(track.name), 0.7);
    };
    // The pose and shape a frame shows: a frame the body missed inside its range keeps the last
    // one it had (it is hidden then anyway).
    std::vector<const BodyKey*> shown;
    const BodyKey* last = nullptr;
    for (const BodyKey& k : track.keys) {
        if (k.shape >= 0) last = &k;
        shown.push_back(last);
    }
    const BodyKey& first = *shown.front();
    tinygltf::Node body;
    body.name = track.name;
    body.translation = {first.translation.x(), first.translation.y(), first.translation.z()};
    body.rotation = {first.rotation.x(), first.rotation.y(), first.rotation.z(), first.rotation.w()};
    if (!track.at(1)) body.scale = {0, 0, 0};
    std::vector<int> shapeMeshes;
    for (size_t s = 0; s < track.shapes.size(); ++s)
        shapeMeshes.push_back(mesh(track.shapes.size() == 1 ? track.name : track.name + " shape " + std::to_string(s),
                                   track.shapes[s], bodyMaterial));
    if (shapeMeshes.size() == 1 && shapeMeshes[0] >= 0) body.mesh = shapeMeshes[0];
    const int bodyNode = node(std::move(body));
    model_.scenes[0].nodes.push_back(bodyNode);

    if (shapeMeshes.size() > 1)
        for (size_t s = 0; s < shapeMeshes.size(); ++s) {
            if (shapeMeshes[s] < 0) continue; // nothing to show while it has that shape
            tinygltf::Node child;
            child.name = track.name + " shape " + std::to_string(s);
            child.mesh = shapeMeshes[s];
            if (first.shape != int(s)) child.scale = {0, 0, 0};
            const int childNode = node(std::move(child));
            model_.nodes[size_t(bodyNode)].children.push_back(childNode);
            visibility(childNode, frameCount, [&](int f) {
                const BodyKey* k = f < track.firstFrame ? nullptr : shown[size_t(std::min(f, track.lastFrame()) - track.firstFrame)];
                return k && k->shape == int(s);
            });
        }

    bool moves = false;
    for (const BodyKey* k : shown)
        moves = moves || k->translation != first.translation || k->rotation.coeffs() != first.rotation.coeffs();
    if (moves) {
        std::vector<float> t, r;
        for (const BodyKey* k : shown) {
            for (int i = 0; i < 3; ++i) t.push_back(float(k->translation[i]));
            const Eigen::Vector4f q = k->rotation.coeffs().cast<float>().normalized(); // x, y, z, w as glTF
            for (int i = 0; i < 4; ++i) r.push_back(q[i]);
        }
        const int input = times(track.firstFrame, track.lastFrame());
        channel(bodyNode, "translation", input, floats(t, TINYGLTF_TYPE_VEC3, 3), "LINEAR");
        channel(bodyNode, "rotation", input, floats(r, TINYGLTF_TYPE_VEC4, 4), "LINEAR");
    }
    visibility(bodyNode, frameCount, [&](int f) { return track.at(f) != nullptr; });
}

} // namespace

GltfStats writeGltf(const RunRecording& recording, double fps, const std::filesystem::path& path) {
    ModelBuilder builder(fps);
    for (const BodyTrack& track : recording.tracks()) builder.addTrack(track, recording.frames());
    tinygltf::Model model = builder.finish();
    tinygltf::Value::Array events;
    for (int n : recording.eventsPerFrame()) events.emplace_back(n);
    tinygltf::Value::Object extras;
    extras["fps"] = tinygltf::Value(fps);
    extras["events_per_frame"] = tinygltf::Value(std::move(events));
    model.scenes[0].extras = tinygltf::Value(std::move(extras));
    std::ostringstream bytes;
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&model, bytes, false, true))
        throw std::runtime_error(path.string() + ": tinygltf could not write the scene");
    const std::string text = std::move(bytes).str();
    writeFile(path, text);
    GltfStats stats;
    stats.bytes = text.size();
    stats.nodes = int(model.nodes.size());
    stats.meshes = int(model.meshes.size());
    stats.animationChannels = model.animations.empty() ? 0 : int(model.animations[0].channels.size());
    return stats;
}

} // namespace shatter::demo
