#pragma once
// The files shatter-mpm leaves in its output directory:
//   tips.csv               time,crack,tip,x,y,J,KI,KII,theta,grew — every active tip, every frame
//   particles_NNNN.csv     id,body,material,x,y,vx,vy,sxx,sxy,syy — every particle, Cauchy stress in Pa
//   cracks_NNNN.csv        crack,point,x,y,above_x,above_y,below_x,below_y — crack particles and
//                          the positions of the two crack surfaces
//   particles_NNNN.vtp, cracks_NNNN.vtp, mpm.pvd — the same for ParaView (VtkSeries.h)
// Frame 0 is the initial state. Numbers are written with 9 significant digits (%.9g), so
// the same run writes the same bytes.
#include "demos/mpm/VtkSeries.h"
#include <shatter/plugin/mpm/Solver2D.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace shatter::mpm::demo {

// "particles_0007.csv": frame numbers padded to the width of the last frame (at least 4).
std::string frameFileName(const std::string& stem, int frame, int lastFrame, const std::string& extension);

class MpmOutput {
public:
    // Creates `dir` (with parents) and removes frame files an earlier run left there.
    MpmOutput(std::filesystem::path dir, int lastFrame);

    void writeFrame(int frame, const Solver2D& solver);
    const std::filesystem::path& dir() const { return dir_; }
    int staleFilesRemoved() const { return staleRemoved_; }

private:
    void writeTips(const Solver2D& solver);
    void writeParticles(int frame, const Solver2D& solver) const;
    void writeCracks(int frame, const Solver2D& solver) const;

    std::filesystem::path dir_;
    int lastFrame_;
    int staleRemoved_ = 0;
    std::ofstream tips_;
    VtkSeries vtk_;
};

} // namespace shatter::mpm::demo
