#pragma once
// How an error message shows bytes taken from an input file: in single quotes, printable
// ASCII as is and every other byte as \xNN (a binary file must not write control codes or
// broken UTF-8 to the user's terminal), cut after `limit` bytes with the full length given.
#include <cstdio>
#include <string>
#include <string_view>

namespace shatter {

// The bytes escaped and cut, without quotes (for a library's message that quotes input itself).
inline std::string printableInput(std::string_view bytes, std::size_t limit) {
    std::string out;
    for (std::size_t i = 0; i < bytes.size() && i < limit; ++i) {
        const unsigned char c = static_cast<unsigned char>(bytes[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02X", c);
            out += hex;
        }
    }
    if (bytes.size() > limit) out += "...";
    return out;
}

inline std::string quoteInput(std::string_view bytes, std::size_t limit = 40) {
    std::string out(1, '\'');
    out += printableInput(bytes, limit);
    out += '\'';
    if (bytes.size() > limit) out += " (" + std::to_string(bytes.size()) + " bytes)";
    return out;
}

} // namespace shatter
