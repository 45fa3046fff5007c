#include "demos/bench/BulletZones.h"

#include <LinearMath/btQuickprof.h>

#include <chrono>
#include <utility>
#include <vector>

namespace shatter::bench {

namespace {

using Clock = std::chrono::steady_clock;

// Bullet's hooks are plain functions: the one active instance's state lives here.
std::vector<std::pair<const char*, Clock::time_point>> open;
std::map<std::string, double> spent;
btEnterProfileZoneFunc* previousEnter = nullptr;
btLeaveProfileZoneFunc* previousLeave = nullptr;

void enter(const char* name) { open.emplace_back(name, Clock::now()); }

void leave() {
    if (open.empty()) return;
    const auto [name, start] = open.back();
    open.pop_back();
    spent[name] += std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

} // namespace

BulletZones::BulletZones() {
    open.clear();
    spent.clear();
    previousEnter = btGetCurrentEnterProfileZoneFunc();
    previousLeave = btGetCurrentLeaveProfileZoneFunc();
    btSetCustomEnterProfileZoneFunc(enter);
    btSetCustomLeaveProfileZoneFunc(leave);
}

BulletZones::~BulletZones() {
    btSetCustomEnterProfileZoneFunc(previousEnter);
    btSetCustomLeaveProfileZoneFunc(previousLeave);
}

std::map<std::string, double> BulletZones::take() {
    std::map<std::string, double> out;
    out.swap(spent);
    return out;
}

} // namespace shatter::bench
