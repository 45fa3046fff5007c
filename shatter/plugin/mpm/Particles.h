#pragma once
// The material points, stored as parallel arrays (one entry per particle) so that the
// transfer loops stream through memory.
#include <shatter/plugin/mpm/Types.h>

#include <cstdint>
#include <vector>

namespace shatter::mpm {

struct Particles {
    std::vector<Vec2> x;        // position, m
    std::vector<Vec2> x0;       // reference position, m (displacement u = x − x0)
    std::vector<Vec2> v;        // velocity, m/s
    std::vector<Mat2> C;        // APIC affine velocity, 1/s (zero under PIC)
    std::vector<Mat2> Fe;       // elastic deformation gradient
    std::vector<Mat2> Fp;       // plastic deformation gradient (identity for elastic models)
    std::vector<double> mass;   // kg (per metre of thickness)
    std::vector<double> volume0; // reference area, m²
    std::vector<std::uint16_t> material;
    std::vector<std::uint16_t> body;
    std::vector<std::uint8_t> fixed; // 1: held in place (velocity boundary condition)

    size_t size() const { return x.size(); }

    void add(const Vec2& position, const Vec2& velocity, double m, double v0, int materialIndex, int bodyIndex) {
        x.push_back(position);
        x0.push_back(position);
        v.push_back(velocity);
        C.push_back(Mat2::Zero());
        Fe.push_back(Mat2::Identity());
        Fp.push_back(Mat2::Identity());
        mass.push_back(m);
        volume0.push_back(v0);
        material.push_back(std::uint16_t(materialIndex));
        body.push_back(std::uint16_t(bodyIndex));
        fixed.push_back(0);
    }
};

} // namespace shatter::mpm
