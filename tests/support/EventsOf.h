#pragma once
// The events of one type, in the order the plugin reported them.
#include <shatter/bullet_ext/Events.h>

#include <vector>

namespace shatter::test {

inline std::vector<Event> eventsOf(std::vector<Event> events, EventType type) {
    std::erase_if(events, [&](const Event& e) { return e.type != type; });
    return events;
}

} // namespace shatter::test
