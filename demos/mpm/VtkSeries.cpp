#include "demos/mpm/VtkSeries.h"

#include "demos/mpm/MpmOutput.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace shatter::mpm::demo {

namespace {

void number(std::string& out, double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g ", v);
    out += text;
}

void integer(std::string& out, long long v) {
    out += std::to_string(v);
    out += ' ';
}

// One <DataArray> element; `values` is the text of its numbers.
void dataArray(std::string& out, const char* type, const char* name, int components, const std::string& values) {
    out += "        <DataArray type=\"";
    out += type;
    out += "\"";
    if (name) out += std::string(" Name=\"") + name + "\"";
    if (components > 1) out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    out += " format=\"ascii\">";
    out += values;
    out += "</DataArray>\n";
}

void writeText(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

std::string polyData(size_t points, const std::string& pointData, const std::string& cellData,
                     const std::string& positions, const char* cells, size_t cellCount, const std::string& connectivity,
                     const std::string& offsets) {
    std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                      "  <PolyData>\n";
    out += "    <Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfVerts=\"" +
           std::to_string(cells[0] == 'V' ? cellCount : 0) + "\" NumberOfLines=\"" +
           std::to_string(cells[0] == 'L' ? cellCount : 0) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
    out += "      <PointData>\n" + pointData + "      </PointData>\n";
    out += "      <CellData>\n" + cellData + "      </CellData>\n";
    out += "      <Points>\n";
    dataArray(out, "Float64", "position", 3, positions);
    out += "      </Points>\n";
    out += std::string("      <") + cells + ">\n";
    dataArray(out, "Int64", "connectivity", 1, connectivity);
    dataArray(out, "Int64", "offsets", 1, offsets);
    out += std::string("      </") + cells + ">\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    return out;
}

std::string particlesFile(const Solver2D& solver) {
    const Particles& P = solver.particles();
    std::string id, body, material, velocity, stress, positions, connectivity, offsets;
    for (size_t p = 0; p < P.size(); ++p) {
        integer(id, (long long)p);
        integer(body, P.body[p]);
        integer(material, P.material[p]);
        for (double v : {P.v[p].x(), P.v[p].y(), 0.0}) number(velocity, v);
        const Mat2 s = solver.cauchyStress(p);
        // Plane: the out-of-plane row and column are left zero.
        for (double v : {s(0, 0), s(0, 1), 0.0, s(1, 0), s(1, 1), 0.0, 0.0, 0.0, 0.0}) number(stress, v);
        for (double v : {P.x[p].x(), P.x[p].y(), 0.0}) number(positions, v);
        integer(connectivity, (long long)p);
        integer(offsets, (long long)p + 1);
    }
    std::string pointData;
    dataArray(pointData, "Int64", "id", 1, id);
    dataArray(pointData, "Int32", "body", 1, body);
    dataArray(pointData, "Int32", "material", 1, material);
    dataArray(pointData, "Float64", "velocity", 3, velocity);
    dataArray(pointData, "Float64", "stress", 9, stress);
    return polyData(P.size(), pointData, "", positions, "Verts", P.size(), connectivity, offsets);
}

std::string cracksFile(const Solver2D& solver) {
    std::string crackOfPoint, opening, positions, connectivity, offsets, crackOfLine;
    long long n = 0;
    for (size_t c = 0; c < solver.cracks().size(); ++c) {
        const Crack& crack = solver.cracks()[c];
        for (size_t k = 0; k < crack.points.size(); ++k) {
            integer(crackOfPoint, (long long)c);
            const Vec2 open = crack.above[k] - crack.below[k];
            for (double v : {open.x(), open.y(), 0.0}) number(opening, v);
            for (double v : {crack.points[k].x(), crack.points[k].y(), 0.0}) number(positions, v);
            integer(connectivity, n++);
        }
        integer(offsets, n);
        integer(crackOfLine, (long long)c);
    }
    std::string pointData, cellData;
    dataArray(pointData, "Int32", "crack", 1, crackOfPoint);
    dataArray(pointData, "Float64", "opening", 3, opening);
    dataArray(cellData, "Int32", "crack", 1, crackOfLine);
    return polyData(size_t(n), pointData, cellData, positions, "Lines", solver.cracks().size(), connectivity, offsets);
}

} // namespace

VtkSeries::VtkSeries(std::filesystem::path dir, int lastFrame) : dir_(std::move(dir)), lastFrame_(lastFrame) {}

void VtkSeries::writeFrame(int frame, const Solver2D& solver) {
    writeText(dir_ / frameFileName("particles", frame, lastFrame_, "vtp"), particlesFile(solver));
    writeText(dir_ / frameFileName("cracks", frame, lastFrame_, "vtp"), cracksFile(solver));
    written_.emplace_back(solver.time(), frame);
    writeIndex();
}

void VtkSeries::writeIndex() const {
    std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
    char line[256];
    for (const auto& [time, frame] : written_) {
        std::snprintf(line, sizeof line, "    <DataSet timestep=\"%.9g\" part=\"0\" file=\"%s\"/>\n", time,
                      frameFileName("particles", frame, lastFrame_, "vtp").c_str());
        out += line;
        std::snprintf(line, sizeof line, "    <DataSet timestep=\"%.9g\" part=\"1\" file=\"%s\"/>\n", time,
                      frameFileName("cracks", frame, lastFrame_, "vtp").c_str());
        out += line;
    }
    out += "  </Collection>\n</VTKFile>\n";
    writeText(dir_ / "mpm.pvd", out);
}

} // namespace shatter::mpm::demo
