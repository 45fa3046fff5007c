#pragma once
// Everything an application needs, in one include: Bullet's own dynamics headers, the plugin
// that attaches to the application's world, visual and breakable bodies and their settings,
// events, mesh loading, and the 2D crack solver with its Bullet collider.
#include <btBulletDynamicsCommon.h>

#include <shatter/bullet_ext/BodySettings.h>
#include <shatter/bullet_ext/Events.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/FractureSystem.h>
#include <shatter/bullet_ext/fracture/TearSystem.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSettings.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/mpm/MpmCollider.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>
#include <shatter/plugin/mpm/SceneFile.h>
#include <shatter/plugin/mpm/Solver2D.h>
