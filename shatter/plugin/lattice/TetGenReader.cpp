#include <shatter/plugin/lattice/TetGenReader.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/QuotedInput.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <new>
#include <sstream>
#include <string_view>
#include <vector>

namespace shatter::lattice {

namespace {

// The non-empty, non-comment lines of a TetGen file held in memory, split into tokens, each
// with its line number; errors read "name:line: ...".
class TokenFile {
public:
    TokenFile(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}
    const std::string& name() const { return name_; }
    int line() const { return line_; }

    // The next line with tokens; false at the end of the text.
    bool next(std::vector<std::string>& tokens) {
        while (pos_ < text_.size()) {
            const size_t end = std::min(text_.find('\n', pos_), text_.size());
            std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++line_;
            line = line.substr(0, std::min(line.find('#'), line.size()));
            tokens.clear();
            for (size_t i = 0; i < line.size();) {
                while (i < line.size() && isBlank(line[i])) ++i;
                const size_t start = i;
                while (i < line.size() && !isBlank(line[i])) ++i;
                if (i > start) tokens.emplace_back(line.substr(start, i - start));
            }
            if (!tokens.empty()) return true;
        }
        return false;
    }
    void expectLine(std::vector<std::string>& tokens, const std::string& what) {
        if (!next(tokens)) fail("ends before " + what);
    }

    // A declared count, and how many entries to reserve: no more than the rest of the text
    // can hold (every entry takes at least `minimumLineBytes` with its newline), so that a
    // header promising 10^12 entries allocates nothing of that size; a file that ends early
    // is then reported at the line where it ends.
    long count(const std::string& token, const std::string& what, size_t minimumLineBytes, size_t& reserve) const {
        const long value = integer(token, what);
        if (value <= 0) fail(what + " must be positive, got " + token);
        if (value > std::numeric_limits<int>::max())
            fail(what + " " + token + " is above the supported " + std::to_string(std::numeric_limits<int>::max()));
        const size_t remaining = text_.size() - std::min(pos_, text_.size());
        reserve = std::min(size_t(value), (remaining + 1) / minimumLineBytes);
        return value;
    }

    [[noreturn]] void fail(const std::string& problem) const {
        throw InputError(name_ + ":" + std::to_string(line_) + ": " + problem);
    }

    long integer(const std::string& token, const std::string& what) const {
        long value = 0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        if (ec != std::errc() || end != token.data() + token.size()) fail(what + " " + quoteInput(token) + " is not an integer");
        return value;
    }
    double real(const std::string& token, const std::string& what) const {
        // strtod rather than from_chars: it accepts every notation TetGen's printf writes.
        char* end = nullptr;
        const double value = std::strtod(token.c_str(), &end);
        if (end != token.c_str() + token.size()) fail(what + " " + quoteInput(token) + " is not a number");
        if (!std::isfinite(value)) fail(what + " " + quoteInput(token) + " is not finite");
        return value;
    }

private:
    static bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

    std::string_view text_;
    std::string name_;
    size_t pos_ = 0;
    int line_ = 0;
};

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError(path + ": read error");
    return std::move(text).str();
}

std::string stemOf(const std::string& path) {
    for (const char* ext : {".node", ".ele"}) {
        const std::string e(ext);
        if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0)
            return path.substr(0, path.size() - e.size());
    }
    return path;
}

struct NodeFile {
    std::vector<Eigen::Vector3d> nodes;
    int base = 0; // index of the first node as written
};

NodeFile readNodes(std::string_view text, const std::string& name) {
    TokenFile file(text, name);
    std::vector<std::string> t;
    file.expectLine(t, "the header '<points> 3 <attributes> <markers>'");
    if (t.size() < 2) file.fail("header needs at least '<points> <dimension>'");
    if (file.integer(t[1], "dimension") != 3) file.fail("dimension must be 3, got " + t[1]);
    size_t reserve = 0;
    const long count = file.count(t[0], "point count", sizeof "0 0 0 0\n" - 1, reserve);
    NodeFile out;
    out.nodes.reserve(reserve);
    for (long i = 0; i < count; ++i) {
        file.expectLine(t, "point " + std::to_string(i + 1) + " of " + std::to_string(count));
        if (t.size() < 4) file.fail("a point line needs '<index> <x> <y> <z>'");
        const long index = file.integer(t[0], "point index");
        if (i == 0) {
            if (index != 0 && index != 1) file.fail("the first point must be numbered 0 or 1, got " + t[0]);
            out.base = int(index);
        } else if (index != out.base + i) {
            file.fail("point numbered " + t[0] + ", expected " + std::to_string(out.base + i) + " (points must be numbered in order)");
        }
        const std::string what = "point " + t[0] + " coordinate";
        out.nodes.emplace_back(file.real(t[1], what), file.real(t[2], what), file.real(t[3], what));
    }
    return out;
}

TetMesh readElements(std::string_view text, const std::string& name, const NodeFile& nodes, std::vector<int>& lines) {
    TokenFile file(text, name);
    std::vector<std::string> t;
    file.expectLine(t, "the header '<tetrahedra> <nodes per tetrahedron> <attributes>'");
    if (t.size() < 2) file.fail("header needs at least '<tetrahedra> <nodes per tetrahedron>'");
    const long corners = file.integer(t[1], "nodes per tetrahedron");
    if (corners != 4 && corners != 10) file.fail("nodes per tetrahedron must be 4 or 10, got " + t[1]);
    size_t reserve = 0;
    const long count = file.count(t[0], "tetrahedron count", 2 * (corners + 1), reserve);
    TetMesh mesh;
    mesh.name = name;
    mesh.nodes = nodes.nodes;
    mesh.tets.reserve(reserve);
    lines.reserve(reserve);
    mesh.tetNumbers.reserve(reserve);
    for (long i = 0; i < count; ++i) {
        file.expectLine(t, "tetrahedron " + std::to_string(i + 1) + " of " + std::to_string(count));
        if (long(t.size()) < 1 + corners) file.fail("a tetrahedron line needs '<index>' and " + std::to_string(corners) + " node indices");
        const long number = file.integer(t[0], "tetrahedron index");
        Tet tet;
        for (int k = 0; k < 4; ++k) {
            const long node = file.integer(t[1 + k], "node index");
            if (node < nodes.base || node >= nodes.base + long(nodes.nodes.size()))
                file.fail("tetrahedron " + t[0] + ": node " + t[1 + k] + " does not exist (the .node file has " +
                          std::to_string(nodes.nodes.size()) + " points numbered from " + std::to_string(nodes.base) + ")");
            tet[k] = int(node - nodes.base);
            for (int j = 0; j < k; ++j)
                if (tet[j] == tet[k]) file.fail("tetrahedron " + t[0] + " uses node " + t[1 + k] + " twice");
        }
        mesh.tets.push_back(tet);
        lines.push_back(file.line());
        mesh.tetNumbers.push_back(number);
    }
    return mesh;
}

bool inverted(const TetMesh& mesh, int t) { return signedVolume(mesh, mesh.tets[t]) < 0; }

// All tets inverted means the file uses the other corner order: reorder with a warning.
// Otherwise the first element with a problem is reported with its file line.
void checkElements(TetMesh& mesh, const std::vector<int>& lines) {
    const auto [earlier, later] = duplicateTets(mesh);
    if (later >= 0)
        throw InputError(mesh.name + ":" + std::to_string(lines[later]) + ": " + tetLabel(mesh, later) + " " +
                         duplicateProblem(mesh, earlier));
    bool allInverted = true;
    for (int t = 0; t < int(mesh.tets.size()) && allInverted; ++t) allInverted = inverted(mesh, t);
    if (allInverted) {
        for (Tet& tet : mesh.tets) std::swap(tet[1], tet[2]);
        mesh.warnings.push_back(mesh.name + ": every tetrahedron has the opposite corner order; all " +
                                std::to_string(mesh.tets.size()) + " were reordered");
    }
    for (int t = 0; t < int(mesh.tets.size()); ++t) {
        const std::string problem = tetProblem(mesh, t);
        if (!problem.empty())
            throw InputError(mesh.name + ":" + std::to_string(lines[t]) + ": " + tetLabel(mesh, t) + " " + problem);
    }
}

} // namespace

TetMesh parseTetGen(const std::string& nodeText, const std::string& eleText, const std::string& stem) {
    try {
        const NodeFile nodes = readNodes(nodeText, stem + ".node");
        std::vector<int> lines;
        TetMesh mesh = readElements(eleText, stem + ".ele", nodes, lines);
        checkElements(mesh, lines);
        validateTetMesh(mesh);
        return mesh;
    } catch (const std::bad_alloc&) {
        throw InputError(stem + ".node/.ele: not enough memory for the mesh");
    }
}

TetMesh readTetGen(const std::string& path) {
    const std::string stem = stemOf(path);
    std::string node, ele;
    try {
        node = readFile(stem + ".node");
        ele = readFile(stem + ".ele");
    } catch (const std::bad_alloc&) {
        throw InputError(stem + ".node/.ele: not enough memory to read the files");
    }
    return parseTetGen(node, ele, stem);
}

void writeTetGen(const TetMesh& mesh, const std::string& stem) {
    auto open = [](const std::string& path) {
        std::ofstream out(path);
        if (!out) throw InputError(path + ": cannot write the file");
        out << std::setprecision(17);
        return out;
    };
    std::ofstream node = open(stem + ".node");
    node << mesh.nodes.size() << " 3 0 0\n";
    for (size_t i = 0; i < mesh.nodes.size(); ++i)
        node << i << ' ' << mesh.nodes[i].x() << ' ' << mesh.nodes[i].y() << ' ' << mesh.nodes[i].z() << '\n';
    std::ofstream ele = open(stem + ".ele");
    ele << mesh.tets.size() << " 4 0\n";
    for (size_t i = 0; i < mesh.tets.size(); ++i) {
        const Tet& t = mesh.tets[i];
        ele << i << ' ' << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
    }
    if (!node || !ele) throw InputError(stem + ": writing the .node/.ele files failed");
}

} // namespace shatter::lattice
