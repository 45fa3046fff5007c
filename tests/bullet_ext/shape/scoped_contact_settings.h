#pragma once
// The world's group contact settings are global (hullPairContacts()): a test that changes them
// puts the defaults back when it ends, so the tests after it see the defaults.
#include <shatter/bullet_ext/shape/HullPairContacts.h>

namespace shatter::test {

// Sets the world's contact settings for one scope and puts the saved ones back after.
class ScopedContactSettings {
public:
    explicit ScopedContactSettings(const HullPairContacts& s) : saved_(hullPairContacts()) { hullPairContacts() = s; }
    ~ScopedContactSettings() { hullPairContacts() = saved_; }
    ScopedContactSettings(const ScopedContactSettings&) = delete;
    ScopedContactSettings& operator=(const ScopedContactSettings&) = delete;

private:
    HullPairContacts saved_;
};

} // namespace shatter::test
