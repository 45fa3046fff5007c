#pragma once
// What happened in the world since the application last drained the queue.
#include <string>
#include <vector>

namespace shatter {

enum class EventType {
    BodyAdded,   // a Shatter body entered the world
    BodyRemoved, // a Shatter body left the world
    JointAdded,  // a joint from a joint box was created
    JointBroken, // a joint's constraint exceeded its breaking impulse and was disabled
    LinksBroken,     // links of a lattice body broke in a step (count = how many; body = the piece)
    FragmentCreated, // a lattice body's piece came apart; this is one new piece (count = its tets)
    BodyDented,      // a plastic body was dented (count = primitives whose rest pose changed)
    DebrisExpired,   // a lattice debris piece outlived DebrisSettings::lifetime or the budget; it is removed (BodyRemoved follows)
    BodyFractured,   // a visual body broke (body = the parent, now removed; fragments = the new bodies' ids)
    BodyTorn,        // a body tore (body, name = the parent as it was; fragments = the parts' body ids; count = connections broken).
                     // A soft parent stays as its largest part (its id among fragments, renamed <name>.k); a plastic one is removed
    JointRecreated,  // a fragment took over a joint of its parent (joint = the copy, body = the fragment, count = the old joint's id)
    BodySubdivided,  // a body with fracture mode Subdivide was cut where hit and stays one body (count = its primitives now)
};

struct Event {
    EventType type;
    int body = -1;    // VisualBody::id() for body events
    int joint = -1;   // Joint::id() for joint events
    double time = 0;  // simulated seconds since the plugin attached
    std::string name; // body or joint name
    int count = 0;    // LinksBroken: links broken; FragmentCreated: tets in the fragment; BodyFractured: fragments; BodyTorn: connections broken
    std::vector<int> fragments; // BodyFractured, BodyTorn: the new bodies' ids
};

const char* toString(EventType type);

} // namespace shatter
