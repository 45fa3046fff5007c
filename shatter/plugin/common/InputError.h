#pragma once
// The one exception type for bad user input (files, settings, poses).
// The message always names the input and says what is wrong with it.
#include <stdexcept>
#include <string>

namespace shatter {

class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

} // namespace shatter
