#include "demos/mpm/MpmOutput.h"

#include <cstdio>
#include <regex>
#include <stdexcept>
#include <vector>

namespace shatter::mpm::demo {

namespace {

// printf into a std::string; the buffer is sized for the longest row we write.
template <class... Args>
std::string format(const char* pattern, Args... args) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, pattern, args...);
    return buffer;
}

std::ofstream openForWriting(const std::filesystem::path& path) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
    return out;
}

} // namespace

std::string frameFileName(const std::string& stem, int frame, int lastFrame, const std::string& extension) {
    const int width = std::max(4, int(std::to_string(lastFrame).size()));
    return stem + "_" + format("%0*d", width, frame) + "." + extension;
}

MpmOutput::MpmOutput(std::filesystem::path dir, int lastFrame)
    : dir_(std::move(dir)), lastFrame_(lastFrame), vtk_(dir_, lastFrame) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec || !std::filesystem::is_directory(dir_))
        throw std::runtime_error(dir_.string() + ": cannot create the output directory (" + ec.message() + ")");
    static const std::regex stale(R"((frame|particles|cracks)_\d{4,}\.(png|csv|vtp))");
    std::vector<std::filesystem::path> remove;
    for (const auto& entry : std::filesystem::directory_iterator(dir_))
        if (entry.is_regular_file() && std::regex_match(entry.path().filename().string(), stale))
            remove.push_back(entry.path());
    for (const auto& p : remove) staleRemoved_ += std::filesystem::remove(p) ? 1 : 0;
    tips_ = openForWriting(dir_ / "tips.csv");
    tips_ << "time,crack,tip,x,y,J,KI,KII,theta,grew\n";
}

void MpmOutput::writeFrame(int frame, const Solver2D& solver) {
    writeTips(solver);
    writeParticles(frame, solver);
    writeCracks(frame, solver);
    vtk_.writeFrame(frame, solver);
}

void MpmOutput::writeTips(const Solver2D& solver) {
    for (const TipResult& t : solver.tips())
        tips_ << format("%.9g,%d,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", solver.time(), t.crack,
                        t.tip == 0 ? "start" : "end", t.position.x(), t.position.y(), t.J, t.KI, t.KII, t.theta,
                        t.grew);
    tips_.flush();
    if (!tips_) throw std::runtime_error((dir_ / "tips.csv").string() + ": write failed");
}

void MpmOutput::writeParticles(int frame, const Solver2D& solver) const {
    const auto path = dir_ / frameFileName("particles", frame, lastFrame_, "csv");
    std::ofstream out = openForWriting(path);
    out << "id,body,material,x,y,vx,vy,sxx,sxy,syy\n";
    const Particles& P = solver.particles();
    for (size_t p = 0; p < P.size(); ++p) {
        const Mat2 s = solver.cauchyStress(p);
        out << format("%zu,%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p, int(P.body[p]), int(P.material[p]),
                      P.x[p].x(), P.x[p].y(), P.v[p].x(), P.v[p].y(), s(0, 0), s(0, 1), s(1, 1));
    }
    if (!out) throw std::runtime_error(path.string() + ": write failed");
}

void MpmOutput::writeCracks(int frame, const Solver2D& solver) const {
    const auto path = dir_ / frameFileName("cracks", frame, lastFrame_, "csv");
    std::ofstream out = openForWriting(path);
    out << "crack,point,x,y,above_x,above_y,below_x,below_y\n";
    const auto& cracks = solver.cracks();
    for (size_t c = 0; c < cracks.size(); ++c)
        for (size_t k = 0; k < cracks[c].points.size(); ++k) {
            const Vec2 x = cracks[c].points[k], a = x + cracks[c].above[k], b = x + cracks[c].below[k];
            out << format("%zu,%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", c, k, x.x(), x.y(), a.x(), a.y(), b.x(), b.y());
        }
    if (!out) throw std::runtime_error(path.string() + ": write failed");
}

} // namespace shatter::mpm::demo
