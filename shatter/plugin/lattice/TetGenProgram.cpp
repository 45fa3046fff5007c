#include <shatter/plugin/lattice/TetGenProgram.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetGenReader.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <unistd.h>

namespace shatter::lattice {

namespace {

namespace fs = std::filesystem;

std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// A fresh directory for one run, removed when the run is over.
class ScratchDirectory {
public:
    ScratchDirectory() {
        static std::atomic<int> counter{0};
        path_ = fs::temp_directory_path() /
                ("shatter_tetgen_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(path_);
    }
    ~ScratchDirectory() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

void writeSmesh(const fs::path& file, const std::vector<Eigen::Vector3d>& positions,
                const std::vector<std::vector<int>>& faces) {
    std::ofstream out(file);
    out << std::setprecision(17) << positions.size() << " 3 0 0\n";
    for (size_t i = 0; i < positions.size(); ++i)
        out << i << ' ' << positions[i].x() << ' ' << positions[i].y() << ' ' << positions[i].z() << '\n';
    out << faces.size() << " 0\n";
    for (const auto& f : faces) {
        out << f.size();
        for (int v : f) out << ' ' << v;
        out << '\n';
    }
    out << "0\n0\n"; // no holes, no regions
    if (!out) throw InputError(file.string() + ": cannot write the TetGen input");
}

} // namespace

bool tetgenAvailable(const std::string& program) {
    // `tetgen -h` exits through an uncaught exception in some builds: ask the shell instead.
    return std::system(("command -v " + quoted(program) + " > /dev/null 2>&1").c_str()) == 0;
}

TetMesh tetrahedralize(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                       const std::vector<std::vector<int>>& faces, const TetGenProgramOptions& o) {
    for (const auto& f : faces)
        for (int v : f)
            if (v < 0 || v >= int(positions.size()))
                throw InputError(name + ": a face uses vertex " + std::to_string(v) + ", which does not exist");
    if (!tetgenAvailable(o.program))
        throw InputError(name + ": the program '" + o.program +
                         "' cannot be run (install Debian's 'tetgen' package; Shatter runs it, never links it)");
    const ScratchDirectory dir;
    const fs::path input = dir.path() / "surface.smesh";
    writeSmesh(input, positions, faces);
    std::ostringstream switches;
    switches << "-pQ";
    if (o.radiusEdgeRatio > 0) switches << "q" << o.radiusEdgeRatio;
    if (o.maxVolume > 0) switches << "a" << o.maxVolume;
    const std::string command = quoted(o.program) + " " + switches.str() + " " + quoted(input.string()) + " > " +
                                quoted((dir.path() / "log.txt").string()) + " 2>&1";
    if (std::system(command.c_str()) != 0) {
        std::ifstream log(dir.path() / "log.txt");
        std::stringstream text;
        text << log.rdbuf();
        throw InputError(name + ": tetgen failed: " + text.str());
    }
    TetMesh mesh = readTetGen((dir.path() / "surface.1").string());
    mesh.name = name;
    return mesh;
}

} // namespace shatter::lattice
