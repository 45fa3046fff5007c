#pragma once
// The run for ParaView (and Python's vtk): per frame, particles_NNNN.vtp (one vertex per
// particle, with id, body, material, velocity and Cauchy stress) and cracks_NNNN.vtp (one
// polyline per crack through its crack particles, with the crack's index and the opening of
// its two surfaces), both VTK XML PolyData in ASCII with 9 significant digits; and mpm.pvd,
// the index of both series by simulated time (ParaView: File > Open mpm.pvd). The index is
// rewritten after every frame, so a run stopped half way still opens.
#include <shatter/plugin/mpm/Solver2D.h>

#include <filesystem>
#include <string>
#include <vector>

namespace shatter::mpm::demo {

class VtkSeries {
public:
    VtkSeries(std::filesystem::path dir, int lastFrame);

    // Throws std::runtime_error naming the file when one cannot be written.
    void writeFrame(int frame, const Solver2D& solver);

private:
    void writeIndex() const;

    std::filesystem::path dir_;
    int lastFrame_;
    std::vector<std::pair<double, int>> written_; // time, frame
};

} // namespace shatter::mpm::demo
