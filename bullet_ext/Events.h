#pragma once
// What happened in the world since the application last drained the queue.
#include <string>

namespace shatter {

enum class EventType {
    BodyAdded,   // a Shatter body entered the world
    BodyRemoved, // a Shatter body left the world
    JointAdded,  // a joint from a joint box was created
    JointBroken, // a joint's constraint exceeded its breaking impulse and was disabled
};

struct Event {
    EventType type;
    int body = -1;    // VisualBody::id() for body events
    int joint = -1;   // Joint::id() for joint events
    double time = 0;  // simulated seconds since the plugin attached
    std::string name; // body or joint name
};

const char* toString(EventType type);

} // namespace shatter
