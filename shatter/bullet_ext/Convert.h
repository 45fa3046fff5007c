#pragma once
// btVector3/btTransform <-> Eigen, in one place. Bullet may be single precision; module math is double.
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace shatter {

inline btVector3 toBullet(const Eigen::Vector3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }
inline Eigen::Vector3d toEigen(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }

inline btMatrix3x3 toBullet(const Eigen::Matrix3d& m) {
    return btMatrix3x3(btScalar(m(0, 0)), btScalar(m(0, 1)), btScalar(m(0, 2)), btScalar(m(1, 0)), btScalar(m(1, 1)),
                       btScalar(m(1, 2)), btScalar(m(2, 0)), btScalar(m(2, 1)), btScalar(m(2, 2)));
}
inline Eigen::Matrix3d toEigen(const btMatrix3x3& m) {
    Eigen::Matrix3d r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = double(m[i][j]);
    return r;
}

// Whether every entry of the transform is finite.
inline bool finite(const btTransform& t) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(t.getOrigin()[i]) || !std::isfinite(t.getBasis()[i].x()) ||
            !std::isfinite(t.getBasis()[i].y()) || !std::isfinite(t.getBasis()[i].z()))
            return false;
    return true;
}

inline btTransform toBullet(const Eigen::Isometry3d& t) { return btTransform(toBullet(Eigen::Matrix3d(t.linear())), toBullet(Eigen::Vector3d(t.translation()))); }
inline Eigen::Isometry3d toEigen(const btTransform& t) {
    Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
    r.linear() = toEigen(t.getBasis());
    r.translation() = toEigen(t.getOrigin());
    return r;
}

} // namespace shatter
