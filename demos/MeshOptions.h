#pragma once
// The options of every demo that loads a user's OBJ file (--mesh): how its coordinates are
// read and how the visual mesh becomes a physical mesh.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <CLI/CLI.hpp>

#include <string>

namespace shatter::demo {

// --units m|cm|mm, --scale F, --thickness M, --density KG_PER_M3, --fill solid|shell,
// --max-primitives N, --max-overlaps-per-primitive N into `settings`.
inline void addMeshOptions(CLI::App& cli, geometry::PhysicalMeshSettings& settings) {
    cli.add_option_function<std::string>(
           "--units", [&settings](const std::string& unit) { settings.units = geometry::lengthUnitNamed(unit); },
           "length unit of the mesh's coordinates: m, cm or mm (default m)")
        ->check(CLI::IsMember({"m", "cm", "mm"}));
    cli.add_option("--scale", settings.scale, "factor on the mesh's coordinates, after --units")->capture_default_str();
    cli.add_option("--thickness", settings.thickness,
                   "extrusion depth of open surfaces in m (0 = 1% of the mesh's bounding-box diagonal)");
    cli.add_option("--density", settings.density, "density in kg/m^3")->capture_default_str();
    cli.add_option_function<std::string>(
           "--fill", [&settings](const std::string& fill) { settings.fill = geometry::fillNamed(fill); },
           "closed meshes weigh as solid objects (solid, default) or as hollow shells of --thickness (shell)")
        ->check(CLI::IsMember({"solid", "shell"}));
    cli.add_option("--max-primitives", settings.maxPrimitives,
                   "most primitives the file may become; more is an error before anything is simulated")
        ->capture_default_str();
    cli.add_option("--max-overlaps-per-primitive", settings.maxOverlapsPerPrimitive,
                   "most pairs of a body's primitives with overlapping boxes (each tested for contact), per primitive")
        ->capture_default_str();
}

} // namespace shatter::demo
