// libFuzzer target (clang, -DSHATTER_FUZZ=ON; scripts/fuzz.sh runs it): see FuzzChecks.h.
#include "tests/fuzz/FuzzChecks.h"

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    if (shatter::test::checkPatternInput(bytes) == shatter::test::FuzzOutcome::Bug) std::abort();
    return 0;
}
