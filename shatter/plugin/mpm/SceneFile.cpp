#include <shatter/plugin/mpm/SceneFile.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/QuotedInput.h>
#include <shatter/plugin/mpm/SceneCheck.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <string_view>
#include <vector>

namespace shatter::mpm {

namespace {

using nlohmann::json;

std::string typeName(const json& j) {
    switch (j.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::string: return "a string";
    case json::value_t::array: return "a list";
    case json::value_t::object: return "an object";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned: return "an integer";
    case json::value_t::number_float: return "a number";
    default: return "an unsupported value";
    }
}

// A JSON value together with its key path, so that every error can name where it is.
class Value {
public:
    Value(const json& j, std::string path, const std::string& source) : j_(j), path_(std::move(path)), source_(source) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(source_ + ": " + (path_.empty() ? std::string("(top level)") : printableInput(path_, 200)) + ": " + what);
    }
    const std::string& path() const { return path_; }
    const json& raw() const { return j_; }

    // Checks that this is an object whose keys are all in `allowed`.
    void expectObject(std::initializer_list<const char*> allowed) const {
        if (!j_.is_object()) fail("expected an object, got " + typeName(j_));
        for (auto it = j_.begin(); it != j_.end(); ++it) {
            bool known = false;
            for (const char* k : allowed) known = known || it.key() == k;
            if (!known) {
                std::string list;
                for (const char* k : allowed) list += (list.empty() ? "" : ", ") + std::string(k);
                child(it.key()).fail("unknown key (expected one of: " + list + ")");
            }
        }
    }
    bool has(const char* key) const { return j_.contains(key); }
    Value child(const std::string& key) const {
        static const json missing;
        const auto it = j_.find(key);
        return Value(it == j_.end() ? missing : *it, join(key), source_);
    }
    Value required(const char* key) const {
        if (!has(key)) fail(std::string("missing required key \"") + key + "\"");
        return child(key);
    }
    Value at(size_t i) const { return Value(j_[i], path_ + "[" + std::to_string(i) + "]", source_); }
    size_t listSize() const {
        if (!j_.is_array()) fail("expected a list, got " + typeName(j_));
        return j_.size();
    }

    double number() const {
        if (!j_.is_number()) fail("expected a number, got " + typeName(j_));
        return j_.get<double>();
    }
    long integer() const {
        if (!j_.is_number_integer()) fail("expected an integer, got " + typeName(j_));
        if (j_.is_number_unsigned() && j_.get<unsigned long>() > (unsigned long)std::numeric_limits<long>::max())
            fail("integer too large, got " + j_.dump());
        return j_.get<long>();
    }
    bool boolean() const {
        if (!j_.is_boolean()) fail("expected true or false, got " + typeName(j_));
        return j_.get<bool>();
    }
    std::string string() const {
        if (!j_.is_string()) fail("expected a string, got " + typeName(j_));
        return j_.get<std::string>();
    }
    Vec2 vec2() const {
        if (!j_.is_array() || j_.size() != 2) fail("expected a list of two numbers [x, y], got " + describe());
        return Vec2(at(0).number(), at(1).number());
    }
    std::vector<Vec2> points() const {
        std::vector<Vec2> out;
        for (size_t i = 0, n = listSize(); i < n; ++i) out.push_back(at(i).vec2());
        return out;
    }
    // One of `choices`, returned as its index.
    int choice(std::initializer_list<const char*> choices) const {
        const std::string s = string();
        int i = 0;
        std::string list;
        for (const char* c : choices) {
            if (s == c) return i;
            list += (list.empty() ? "\"" : ", \"") + std::string(c) + "\"";
            ++i;
        }
        fail("\"" + printableInput(s, 40) + "\" is not one of " + list);
    }

private:
    std::string join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    std::string describe() const {
        if (j_.is_array()) return "a list of " + std::to_string(j_.size());
        return typeName(j_);
    }

    const json& j_;
    std::string path_;
    const std::string& source_;
};

double optionalNumber(const Value& v, const char* key, double fallback) {
    return v.has(key) ? v.child(key).number() : fallback;
}

Box readBox(const Value& v) {
    v.expectObject({"min", "max"});
    return Box{v.required("min").vec2(), v.required("max").vec2()};
}

Shape readShape(const Value& v) {
    if (!v.raw().is_object()) v.fail("expected an object, got " + typeName(v.raw()));
    const int type = v.required("type").choice({"rect", "circle", "polygon"});
    if (type == 0) {
        v.expectObject({"type", "min", "max"});
        return Shape(RectShape{v.required("min").vec2(), v.required("max").vec2()});
    }
    if (type == 1) {
        v.expectObject({"type", "center", "radius"});
        return Shape(CircleShape{v.required("center").vec2(), v.required("radius").number()});
    }
    v.expectObject({"type", "points"});
    return Shape(PolygonShape{v.required("points").points()});
}

Material readMaterial(const Value& v, const std::string& name) {
    v.expectObject({"preset", "model", "E", "nu", "rho", "Kc", "theta_c", "theta_s", "xi"});
    Material m;
    const bool preset = v.has("preset");
    if (preset) {
        const std::string p = v.child("preset").string();
        const auto found = materialPreset(p);
        if (!found) v.child("preset").fail("\"" + printableInput(p, 40) + "\" is not one of \"snow\", \"pmma\", \"glass\", \"jello\"");
        m = *found;
    }
    m.name = name;
    auto get = [&](const char* key, double& target) {
        if (v.has(key)) target = v.child(key).number();
        else if (!preset) v.fail(std::string("missing required key \"") + key + "\" (or give a \"preset\")");
    };
    if (v.has("model") || !preset)
        m.model = ConstitutiveModelType(v.required("model").choice({"linear_elastic", "corotated", "snow"}));
    get("E", m.E);
    get("nu", m.nu);
    get("rho", m.rho);
    if (v.has("Kc")) m.Kc = v.child("Kc").number();
    if (v.has("theta_c")) m.thetaC = v.child("theta_c").number();
    if (v.has("theta_s")) m.thetaS = v.child("theta_s").number();
    if (v.has("xi")) m.xi = v.child("xi").number();
    return m;
}

void readMaterials(const Value& v, Scene& scene, std::map<std::string, int>& index) {
    if (!v.raw().is_object()) v.fail("expected an object of named materials, got " + typeName(v.raw()));
    if (v.raw().empty()) v.fail("needs at least one material");
    for (auto it = v.raw().begin(); it != v.raw().end(); ++it) {
        index[it.key()] = int(scene.materials.size());
        scene.materials.push_back(readMaterial(v.child(it.key()), it.key()));
    }
}

std::string materialList(const std::map<std::string, int>& index) {
    std::string list;
    for (const auto& [name, i] : index) list += (list.empty() ? "" : ", ") + printableInput(name, 40);
    return list;
}

void readBodies(const Value& v, Scene& scene, const std::map<std::string, int>& materials) {
    const size_t n = v.listSize();
    if (n == 0) v.fail("needs at least one body");
    for (size_t i = 0; i < n; ++i) {
        const Value b = v.at(i);
        b.expectObject({"shape", "material", "velocity"});
        Body body;
        body.shape = readShape(b.required("shape"));
        const std::string name = b.required("material").string();
        const auto found = materials.find(name);
        if (found == materials.end())
            b.child("material").fail("no material named \"" + printableInput(name, 40) + "\" (materials: " + materialList(materials) + ")");
        body.material = found->second;
        if (b.has("velocity")) body.velocity = b.child("velocity").vec2();
        scene.bodies.push_back(std::move(body));
    }
}

void readCracks(const Value& v, Scene& scene) {
    for (size_t i = 0, n = v.listSize(); i < n; ++i) {
        const Value c = v.at(i);
        c.expectObject({"points", "propagate", "tips", "guide"});
        CrackSpec spec;
        spec.points = c.required("points").points();
        if (c.has("propagate")) spec.propagate = c.child("propagate").boolean();
        if (c.has("tips")) spec.tips = TipSelection(c.child("tips").choice({"both", "start", "end", "none"}));
        if (c.has("guide")) spec.guide = c.child("guide").points();
        scene.cracks.push_back(std::move(spec));
    }
}

void readLoads(const Value& v, Scene& scene) {
    for (size_t i = 0, n = v.listSize(); i < n; ++i) {
        const Value l = v.at(i);
        l.expectObject({"region", "traction", "pressure", "force", "facing", "ramp"});
        Load load;
        load.region = readBox(l.required("region"));
        if (int(l.has("traction")) + int(l.has("pressure")) + int(l.has("force")) != 1)
            l.fail("needs exactly one of \"traction\" (Pa), \"pressure\" (Pa) and \"force\" (N)");
        if (l.has("pressure")) {
            load.kind = Load::Kind::Pressure;
            load.pressure = l.child("pressure").number();
        } else {
            load.kind = l.has("traction") ? Load::Kind::Traction : Load::Kind::Force;
            load.value = l.child(l.has("traction") ? "traction" : "force").vec2();
        }
        if (l.has("facing")) {
            const Value f = l.child("facing");
            load.facing = f.vec2();
            if (!(load.facing.norm() > 0)) f.fail("must be a non-zero direction");
            if (load.kind == Load::Kind::Force) f.fail("applies to traction and pressure loads, not to a force");
            load.facing.normalize();
        }
        load.ramp = optionalNumber(l, "ramp", 0);
        scene.loads.push_back(load);
    }
}

std::shared_ptr<const Collider> readCollider(const Value& c) {
    if (!c.raw().is_object()) c.fail("expected an object, got " + typeName(c.raw()));
    const int type = c.required("type").choice({"half_plane", "box", "circle"});
    const double friction = optionalNumber(c, "friction", 0);
    if (!(friction >= 0) || !std::isfinite(friction)) c.child("friction").fail("must be a finite number >= 0");
    if (type == 0) {
        c.expectObject({"type", "point", "normal", "friction"});
        const Vec2 normal = c.required("normal").vec2();
        if (!(normal.norm() > 0) || !normal.allFinite()) c.child("normal").fail("must be a non-zero finite vector");
        return std::make_shared<HalfPlaneCollider>(c.required("point").vec2(), normal, friction);
    }
    if (type == 1) {
        c.expectObject({"type", "min", "max", "friction"});
        const Box box{c.required("min").vec2(), c.required("max").vec2()};
        if (!(box.min.array() < box.max.array()).all()) c.fail("min must be below max on both axes");
        return std::make_shared<BoxCollider>(box, friction);
    }
    c.expectObject({"type", "center", "radius", "friction"});
    const double radius = c.required("radius").number();
    if (!(radius > 0)) c.child("radius").fail("must be > 0");
    return std::make_shared<CircleCollider>(c.required("center").vec2(), radius, friction);
}

void readFracture(const Value& v, CrackGrowthSettings& f) {
    v.expectObject({"contour_radius", "contour_segments", "growth", "mixity_tolerance", "speed_limit", "filter",
                    "analysis_interval"});
    f.contourRadiusCells = optionalNumber(v, "contour_radius", f.contourRadiusCells);
    if (v.has("contour_segments")) {
        const long segments = v.child("contour_segments").integer();
        if (segments < 2 || segments > 4096) v.child("contour_segments").fail("must be an even number from 2 to 4096");
        f.contourSegments = int(segments);
    }
    f.growthCells = optionalNumber(v, "growth", f.growthCells);
    f.mixityTolerance = optionalNumber(v, "mixity_tolerance", f.mixityTolerance);
    f.speedLimit = optionalNumber(v, "speed_limit", f.speedLimit);
    f.filterTransits = optionalNumber(v, "filter", f.filterTransits);
    f.analysisCells = optionalNumber(v, "analysis_interval", f.analysisCells);
}

Scene readScene(const Value& root) {
    root.expectObject({"analysis", "gravity", "grid", "time", "transfer", "materials", "bodies", "cracks", "loads",
                       "fixed", "colliders", "damping", "fracture", "seed"});
    Scene s;
    if (root.has("analysis")) s.analysis = Analysis(root.child("analysis").choice({"plane_stress", "plane_strain"}));
    s.gravity = root.has("gravity") ? root.child("gravity").vec2() : Vec2(0, -9.81);
    const Value grid = root.required("grid");
    grid.expectObject({"dx", "ppc", "kernel", "jitter"});
    s.grid.dx = grid.required("dx").number();
    if (grid.has("ppc")) {
        const long ppc = grid.child("ppc").integer();
        if (ppc < 1 || ppc > 16) grid.child("ppc").fail("must be an integer from 1 to 16 (particles per cell per axis)");
        s.grid.ppc = int(ppc);
    }
    if (grid.has("kernel")) s.grid.kernel = KernelType(grid.child("kernel").choice({"cubic", "quadratic"}));
    s.grid.jitter = optionalNumber(grid, "jitter", 0);
    const Value time = root.required("time");
    time.expectObject({"end", "frame", "cfl", "max_step"});
    s.time.end = time.required("end").number();
    s.time.frame = optionalNumber(time, "frame", s.time.frame);
    s.time.cfl = optionalNumber(time, "cfl", s.time.cfl);
    s.time.maxStep = optionalNumber(time, "max_step", s.time.maxStep);
    if (root.has("transfer")) s.transfer = VelocityTransfer(root.child("transfer").choice({"apic", "pic"}));
    std::map<std::string, int> materials;
    readMaterials(root.required("materials"), s, materials);
    readBodies(root.required("bodies"), s, materials);
    if (root.has("cracks")) readCracks(root.child("cracks"), s);
    if (root.has("loads")) readLoads(root.child("loads"), s);
    if (root.has("fixed"))
        for (size_t i = 0, n = root.child("fixed").listSize(); i < n; ++i) s.fixed.push_back(readBox(root.child("fixed").at(i)));
    if (root.has("colliders"))
        for (size_t i = 0, n = root.child("colliders").listSize(); i < n; ++i)
            s.colliders.push_back(readCollider(root.child("colliders").at(i)));
    s.damping = optionalNumber(root, "damping", 0);
    if (root.has("fracture")) readFracture(root.child("fracture"), s.fracture);
    if (root.has("seed")) {
        const long seed = root.child("seed").integer();
        if (seed < 0) root.child("seed").fail("must be >= 0");
        s.seed = std::uint64_t(seed);
    }
    return s;
}

// Where the parser is, as a key path ("bodies[0].shape.radius"), kept up to date by the
// parser's callback so that an error the library raises mid-value (a number too large for a
// double) can name the key it belongs to.
class ParsePosition {
public:
    bool event(json::parse_event_t event, const json& parsed) {
        using E = json::parse_event_t;
        if ((event == E::value || event == E::object_start || event == E::array_start) && !open_.empty() &&
            open_.back().isArray)
            ++open_.back().elements;
        if (event == E::object_start || event == E::array_start) open_.push_back({event == E::array_start, 0, {}});
        else if (event == E::object_end || event == E::array_end) open_.pop_back();
        else if (event == E::key && !open_.empty()) open_.back().key = parsed.get<std::string>();
        return true;
    }
    // The key or list element being read: the innermost list's next element, an outer list's
    // open one.
    std::string path() const {
        std::string out;
        for (size_t i = 0; i < open_.size(); ++i) {
            const Open& o = open_[i];
            if (o.isArray) out += "[" + std::to_string(i + 1 == open_.size() ? o.elements : o.elements - 1) + "]";
            else if (!o.key.empty()) out += (out.empty() ? "" : ".") + printableInput(o.key, 60);
        }
        return out.empty() ? "(top level)" : out;
    }

private:
    struct Open {
        bool isArray;
        long elements;
        std::string key;
    };
    std::vector<Open> open_;
};

// The library's message without its "[json.exception.x.n] " tag, input bytes escaped.
std::string libraryMessage(const json::exception& e) {
    std::string_view what = e.what();
    if (!what.empty() && what.front() == '[') what.remove_prefix(std::min(what.find("] ") + 2, what.size()));
    return printableInput(what, 300);
}

json parseJson(const std::string& text, const std::string& source) {
    ParsePosition position;
    try {
        return json::parse(text, [&position](int, json::parse_event_t event, json& parsed) {
            return position.event(event, parsed);
        });
    } catch (const json::parse_error& e) {
        throw InputError(source + ": not valid JSON: " + libraryMessage(e));
    } catch (const json::exception& e) {
        throw InputError(source + ": " + position.path() + ": " + libraryMessage(e));
    }
}

} // namespace

Scene parseScene(const std::string& text, const std::string& source) {
    try {
        Scene scene = readScene(Value(parseJson(text, source), "", source));
        scene.source = source;
        checkScene(scene);
        return scene;
    } catch (const std::bad_alloc&) {
        throw InputError(source + ": not enough memory for the scene");
    }
}

Scene loadScene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the scene file");
    std::ostringstream text;
    text << in.rdbuf();
    return parseScene(text.str(), path);
}

} // namespace shatter::mpm
