#include <shatter/bullet_ext/Events.h>

namespace shatter {

const char* toString(EventType type) {
    switch (type) {
    case EventType::BodyAdded: return "body_added";
    case EventType::BodyRemoved: return "body_removed";
    case EventType::JointAdded: return "joint_added";
    case EventType::JointBroken: return "joint_broken";
    case EventType::LinksBroken: return "links_broken";
    case EventType::FragmentCreated: return "fragment_created";
    case EventType::BodyDented: return "body_dented";
    case EventType::DebrisExpired: return "debris_expired";
    case EventType::BodyFractured: return "body_fractured";
    case EventType::BodyTorn: return "body_torn";
    case EventType::JointRecreated: return "joint_recreated";
    }
    return "unknown";
}

} // namespace shatter
