// libFuzzer entry point for the OBJ path (built only with clang and -DSHATTER_FUZZ=ON):
//   CXX=clang++ cmake -S . -B build-fuzz -DSHATTER_FUZZ=ON -DSHATTER_SANITIZE=ON
//   cmake --build build-fuzz --target shatter-fuzz-obj && build-fuzz/bin/shatter-fuzz-obj demos/assets -max_total_time=60
#include "tests/fuzz/ObjFuzzCheck.h"

#include <cstdint>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    if (shatter::test::checkObjInput(text) == shatter::test::ObjOutcome::Bug) std::abort();
    return 0;
}
