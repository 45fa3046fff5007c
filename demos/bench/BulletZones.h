#pragma once
// Time spent in Bullet's own profile zones (BT_PROFILE: Debian's Bullet is built with them),
// summed per zone name until taken. Installs itself as Bullet's profile zone hooks; one
// instance at a time. Costs two clock reads per zone (about 30 zones per internal step).
#include <map>
#include <string>

namespace shatter::bench {

class BulletZones {
public:
    BulletZones();  // installs the hooks
    ~BulletZones(); // removes them
    BulletZones(const BulletZones&) = delete;
    BulletZones& operator=(const BulletZones&) = delete;

    // Milliseconds per zone name since the last call (inclusive of nested zones); cleared.
    std::map<std::string, double> take();
};

} // namespace shatter::bench
