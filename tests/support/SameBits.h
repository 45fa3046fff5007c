#pragma once
// Equality of two numbers' bits: tells -0 from +0 and a NaN from another, which == cannot.
#include <cstring>
#include <type_traits>

namespace shatter::test {

template <typename T>
    requires std::is_arithmetic_v<T>
bool sameBits(T a, T b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace shatter::test
