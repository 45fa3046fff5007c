#pragma once
// The hull-pair contact settings as command-line options, shared by the benches that time
// scenes with many touching hulls (lattice and fracture), so both expose the same levers.
#include <shatter/bullet_ext/shape/HullPairContacts.h>

#include <CLI/CLI.hpp>

namespace shatter::bench {

inline void addContactOptions(CLI::App& app) {
    app.add_option("--pair-list-slack", shatter::hullPairContacts().pairListSlack,
                   "group pairs reuse their list of primitive pairs until they have moved this far (m); 0: walk the "
                   "trees every step")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--reclip-after", shatter::hullPairContacts().reclipAfter,
                   "hull pairs are clipped again after moving this fraction of their contact breaking threshold "
                   "(relative to each other) since the last clip; 0: every step, as Bullet does")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_flag_callback(
        "--ordered-contacts",
        [] { shatter::hullPairContacts().contactOrder = shatter::HullPairContacts::ContactOrder::Own; },
        "the solver takes contact manifolds by bodies and leaf pair, not by their places in the dispatcher; a "
        "group's hull leaf pair then holds a manifold only while it has points");
    app.add_flag("--keep-empty-leaf-manifolds", shatter::hullPairContacts().keepEmptyLeafManifolds,
                 "with --ordered-contacts: a group's hull leaf pair keeps its manifold while listed, empty or not "
                 "(always so without)");
}

} // namespace shatter::bench
