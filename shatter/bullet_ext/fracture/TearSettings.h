#pragma once
// When a soft visual body tears (source 000 §3.6): a connection between two primitives breaks
// when vertices the two share (same global id, same rest position) have drifted more than
// `distance` apart; the parts that no longer hang together become bodies of their own. Off by
// default. Units SI.
#include <string>

namespace shatter {

struct TearSettings {
    bool enabled = false;
    // m (an absolute length, not a fraction of the primitive size): a breakable connection
    // breaks when two of its vertices that share a global id are farther apart than this.
    double distance = 0.01;
    // Every connection may break (the initial tessellation shows where it tears); false: only
    // the connections across the body's tear lines (`tear.<body>` polylines in the OBJ file,
    // PhysicalMesh::tearEdges), so it tears where the artist drew and nowhere else.
    bool everywhere = false;

    // Distance positive and finite. Checked only when enabled.
    void check(const std::string& body) const;
};

} // namespace shatter
