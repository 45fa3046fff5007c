// Our own OBJ reader: strict numbers (std::from_chars) and an error that names the file
// and line for every malformed statement (third_party_notes/tinyobjloader.md says why).
#include <shatter/plugin/geometry/Aabb.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/QuotedInput.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/Polygon.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <string_view>

namespace shatter::geometry {

namespace {

// Statements we know and deliberately skip (texture, normals, curves, materials, ...).
constexpr std::string_view kIgnored[] = {
    "vt", "vn", "vp", "p", "s", "usemtl", "mtllib", "cstype", "deg", "bmat", "step",
    "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con", "mg", "lod",
    "bevel", "c_interp", "d_interp", "usemap", "maptype", "shadow_obj", "trace_obj", "ctech", "stech", "call", "csh"};

// Share of the squared file diagonal below which a face's Newell normal means zero area.
constexpr double kZeroArea = 1e-12;

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

void splitTokens(std::string_view s, std::vector<std::string_view>& out) {
    out.clear();
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && isBlank(s[i])) ++i;
        const size_t start = i;
        while (i < s.size() && !isBlank(s[i])) ++i;
        if (i > start) out.push_back(s.substr(start, i - start));
    }
}

// Whether a decimal token that from_chars found out of range is too large (rather than
// too small): the decimal exponent of its leading digit is positive.
bool overflows(std::string_view t) {
    size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
    long long magnitude = 0;
    bool found = false, afterPoint = false;
    for (; i < t.size() && t[i] != 'e' && t[i] != 'E'; ++i) {
        if (t[i] == '.') {
            afterPoint = true;
        } else if (found) {
            if (!afterPoint) ++magnitude;
        } else if (t[i] != '0') {
            found = true;
            if (afterPoint) --magnitude;
        } else if (afterPoint) {
            --magnitude;
        }
    }
    if (i + 1 < t.size()) {
        std::string_view e = t.substr(i + 1);
        const bool negative = e.front() == '-';
        if (e.front() == '+' || e.front() == '-') e.remove_prefix(1);
        // Clamped so that the sum cannot overflow: the digit count is far below LLONG_MAX / 4.
        long long exponent = 0;
        const auto r = std::from_chars(e.data(), e.data() + e.size(), exponent);
        if (r.ec == std::errc::result_out_of_range || exponent > LLONG_MAX / 4) exponent = LLONG_MAX / 4;
        magnitude += negative ? -exponent : exponent;
    }
    return magnitude > 0;
}

enum class NumberStatus { Ok, Malformed, NonFinite };

NumberStatus parseNumber(std::string_view token, double& value) {
    std::string_view t = token;
    if (t.size() > 1 && t[0] == '+' && t[1] != '+' && t[1] != '-') t.remove_prefix(1); // from_chars rejects '+'
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value, std::chars_format::general);
    if (end != t.data() + t.size()) return NumberStatus::Malformed;
    if (ec == std::errc::result_out_of_range) {
        if (overflows(t)) return NumberStatus::NonFinite;
        value = t[0] == '-' ? -0.0 : 0.0; // underflow: the value is zero to double precision
        return NumberStatus::Ok;
    }
    if (ec != std::errc()) return NumberStatus::Malformed;
    return std::isfinite(value) ? NumberStatus::Ok : NumberStatus::NonFinite;
}

std::string stemOf(const std::string& name) {
    const std::string stem = std::filesystem::path(name).stem().string();
    return stem.empty() ? name : stem;
}

std::string lineList(const std::vector<int>& lines) {
    std::string out = lines.size() == 1 ? "line " : "lines ";
    for (size_t i = 0; i < lines.size() && i < 5; ++i) {
        if (i) out += ", ";
        out += std::to_string(lines[i]);
    }
    if (lines.size() > 5) out += ", ...";
    return out;
}

class ObjParser {
public:
    ObjParser(std::string_view text, const std::string& name) : text_(text), name_(name) {
        file_.path = name;
        file_.objects.push_back({stemOf(name), 0, {}, {}});
    }

    ObjFile run() {
        readStatements();
        dropDegenerateFaces();
        reportIgnored();
        std::erase_if(file_.objects, [](const ObjObject& o) { return o.faces.empty() && o.polylines.empty(); });
        if (std::none_of(file_.objects.begin(), file_.objects.end(), [](const ObjObject& o) { return !o.faces.empty(); }))
            throw InputError(name_ + ": no faces");
        return std::move(file_);
    }

private:
    [[noreturn]] void fail(const std::string& problem) const {
        throw InputError(name_ + ":" + std::to_string(line_) + ": " + problem);
    }

    // Joins `\` continuations, drops comments and CR, and hands each statement on.
    void readStatements() {
        std::string_view text = text_;
        if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3); // UTF-8 byte order mark
        std::string statement;
        int lineNumber = 0;
        size_t pos = 0;
        while (pos < text.size()) {
            const size_t end = std::min(text.find('\n', pos), text.size());
            std::string_view line = text.substr(pos, end - pos);
            pos = end + 1;
            ++lineNumber;
            line = line.substr(0, std::min(line.find('#'), line.size()));
            while (!line.empty() && isBlank(line.back())) line.remove_suffix(1);
            if (statement.empty()) line_ = lineNumber;
            const bool continues = !line.empty() && line.back() == '\\';
            if (continues) line.remove_suffix(1);
            statement.append(line);
            if (continues) {
                statement.push_back(' ');
                continue;
            }
            handle(statement);
            statement.clear();
        }
        if (!statement.empty()) handle(statement);
    }

    void handle(std::string_view statement) {
        splitTokens(statement, tokens_);
        if (tokens_.empty()) return;
        const std::string_view keyword = tokens_.front();
        if (keyword == "v") readVertex();
        else if (keyword == "f") readFace();
        else if (keyword == "l") readPolyline();
        else if (keyword == "o" || keyword == "g") startObject();
        else if (keyword == "vt") ++textureCount_;
        else if (keyword == "vn") ++normalCount_;
        else if (std::find(std::begin(kIgnored), std::end(kIgnored), keyword) == std::end(kIgnored))
            unknownLines_.push_back(line_);
    }

    void readVertex() {
        if (tokens_.size() < 4)
            fail("vertex needs 3 coordinates (x y z), got " + std::to_string(tokens_.size() - 1));
        double xyz[3] = {0.0, 0.0, 0.0};
        // Extra numbers (w, or r g b colours) are checked but not kept.
        for (size_t i = 1; i < tokens_.size(); ++i) {
            double value = 0.0;
            switch (parseNumber(tokens_[i], value)) {
            case NumberStatus::Malformed: fail("malformed number " + quoteInput(tokens_[i]));
            case NumberStatus::NonFinite: fail("non-finite coordinate " + quoteInput(tokens_[i]));
            case NumberStatus::Ok: break;
            }
            if (i <= 3) xyz[i - 1] = value;
        }
        file_.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
        file_.positionLines.push_back(line_);
    }

    // An OBJ index (1-based, or negative = relative to the end so far) → 0-based.
    // `statement` names what the element belongs to in messages ("face" or "line").
    int resolveIndex(std::string_view token, std::string_view element, const char* what, int countSoFar,
                     const char* statement = "face") const {
        int index = 0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), index);
        if (ec == std::errc::result_out_of_range && end == token.data() + token.size())
            fail(std::string(what) + " index " + quoteInput(token, 24) + " is out of range: " +
                 std::to_string(countSoFar) + " defined before this line");
        if (token.empty() || ec != std::errc() || end != token.data() + token.size())
            fail("malformed " + std::string(what) + " index " + quoteInput(token) + " in " + statement + " element " +
                 quoteInput(element));
        if (index == 0) fail(std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
        const long long resolved = index > 0 ? (long long)index - 1 : (long long)countSoFar + index;
        if (resolved < 0 || resolved >= countSoFar)
            fail(std::string(what) + " index " + std::to_string(index) + " is out of range: " +
                 std::to_string(countSoFar) + " defined before this line");
        return int(resolved);
    }

    // A face needs three vertex references; fewer is malformed (often a truncated file), not
    // degenerate geometry, so it is an error rather than a skipped face.
    void readFace() {
        if (tokens_.size() < 4)
            fail("face needs at least 3 vertices, got " + std::to_string(tokens_.size() - 1) +
                 (tokens_.size() == 1 ? "" : " (is the file cut short?)"));
        ObjFace face;
        face.line = line_;
        for (size_t i = 1; i < tokens_.size(); ++i) {
            const std::string_view element = tokens_[i];
            std::string_view parts[3];
            size_t count = 0, start = 0;
            while (true) {
                const size_t slash = element.find('/', start);
                if (count == 3) fail("malformed face element " + quoteInput(element) + " (more than v/vt/vn)");
                parts[count++] = element.substr(start, slash == std::string_view::npos ? slash : slash - start);
                if (slash == std::string_view::npos) break;
                start = slash + 1;
            }
            face.vertices.push_back(resolveIndex(parts[0], element, "vertex", int(file_.positions.size())));
            if (count > 1 && !parts[1].empty()) resolveIndex(parts[1], element, "texture coordinate", textureCount_);
            if (count > 2) resolveIndex(parts[2], element, "normal", normalCount_);
        }
        file_.objects.back().faces.push_back(std::move(face));
    }

    // A polyline needs two points; its elements are `v` or `v/vt`.
    void readPolyline() {
        if (tokens_.size() < 3) fail("line needs at least 2 vertices, got " + std::to_string(tokens_.size() - 1));
        ObjPolyline polyline;
        polyline.line = line_;
        for (size_t i = 1; i < tokens_.size(); ++i) {
            const std::string_view element = tokens_[i];
            const size_t slash = element.find('/');
            const std::string_view v = element.substr(0, slash);
            if (slash != std::string_view::npos) {
                const std::string_view vt = element.substr(slash + 1);
                if (vt.find('/') != std::string_view::npos)
                    fail("malformed line element " + quoteInput(element) + " (only v or v/vt)");
                if (!vt.empty()) resolveIndex(vt, element, "texture coordinate", textureCount_, "line");
            }
            polyline.vertices.push_back(resolveIndex(v, element, "vertex", int(file_.positions.size()), "line"));
        }
        file_.objects.back().polylines.push_back(std::move(polyline));
    }

    void startObject() {
        std::string name;
        for (size_t i = 1; i < tokens_.size(); ++i) {
            if (i > 1) name += ' ';
            name.append(tokens_[i]);
        }
        if (name.empty()) name = stemOf(name_);
        // Names end up in messages ("body 'NAME'"): bytes outside printable ASCII are kept as
        // \xNN text, so that no message writes raw bytes to a terminal.
        file_.objects.push_back({printableInput(name, name.size()), line_, {}, {}});
    }

    // Fewer than 3 distinct vertices, a vertex repeated, or zero area (Newell normal no
    // longer than 1e-12 × the file's squared bounding-box diagonal).
    void dropDegenerateFaces() {
        Aabb bounds;
        for (const auto& p : file_.positions) bounds.extend(p);
        const double diagonal = bounds.diagonal();
        std::vector<int> lines;
        for (auto& object : file_.objects)
            std::erase_if(object.faces, [&](ObjFace& face) {
                const bool bad = cleanPolygon(file_.positions, face.vertices, kZeroArea * diagonal * diagonal, false) !=
                                 PolygonDefect::Kept;
                if (bad) lines.push_back(face.line);
                return bad;
            });
        if (lines.empty()) return;
        std::sort(lines.begin(), lines.end());
        file_.warnings.push_back(name_ + ": skipped " + std::to_string(lines.size()) + " degenerate face" +
                                 (lines.size() == 1 ? "" : "s") + " (" + lineList(lines) + ")");
    }

    void reportIgnored() {
        if (unknownLines_.empty()) return;
        file_.warnings.push_back(name_ + ": ignored " + std::to_string(unknownLines_.size()) + " unknown statement" +
                                 (unknownLines_.size() == 1 ? "" : "s") + " (" + lineList(unknownLines_) + ")");
    }

    std::string_view text_;
    const std::string& name_;
    ObjFile file_;
    std::vector<std::string_view> tokens_;
    int line_ = 0; // line of the statement being read
    int textureCount_ = 0;
    int normalCount_ = 0;
    std::vector<int> unknownLines_;
};

} // namespace

ObjFile parseObj(const std::string& text, const std::string& name) {
    try {
        return ObjParser(text, name).run();
    } catch (const std::bad_alloc&) {
        throw InputError(name + ": not enough memory for the mesh");
    }
}

ObjFile loadObj(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": cannot open: " + std::strerror(EISDIR));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open: " + std::strerror(errno));
    errno = 0;
    std::string text;
    try {
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } catch (const std::bad_alloc&) {
        throw InputError(path + ": not enough memory to read the file");
    }
    if (in.bad()) throw InputError(path + ": cannot read: " + std::strerror(errno ? errno : EIO));
    return parseObj(text, path);
}

} // namespace shatter::geometry
