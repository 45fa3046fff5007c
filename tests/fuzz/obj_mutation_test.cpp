// Seeded mutation fuzzing of the OBJ path, run in every test pass: whatever the bytes, loading
// and building a physical object either succeeds or throws shatter::InputError — never a
// crash, a hang, another exception type, or a primitive with a non-finite vertex.
// (tests/fuzz/targets/obj_fuzzer.cpp runs the same check under libFuzzer for longer campaigns.)
#include "tests/fuzz/FuzzChecks.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

namespace {

std::string readAsset(const char* name) {
    std::ifstream in(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/" + name, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// One random edit: flip a byte, insert a token OBJ cares about, or cut a piece out.
std::string mutate(std::string text, std::mt19937_64& rng) {
    static const char* tokens[] = {" ", "\n", "-", "/", "//", "0", "1e308", "1e999", "nan", "inf", "-1", "999999",
                                   "f ", "v ", "o joint.hinge.a.b\n", "g ", "\r\n", "\\\n", "#", "."};
    const int edits = 1 + int(rng() % 8);
    for (int e = 0; e < edits && !text.empty(); ++e) {
        const size_t at = rng() % text.size();
        switch (rng() % 3) {
        case 0: text[at] = char(rng() % 256); break;
        case 1: text.insert(at, tokens[rng() % std::size(tokens)]); break;
        default: text.erase(at, 1 + rng() % 16); break;
        }
    }
    return text;
}

} // namespace

TEST(ObjFuzz, MutatedFilesGiveResultsOrInputErrors) {
    const std::string seeds[] = {readAsset("chair.obj"), readAsset("hinged_planks.obj"), readAsset("bowl.obj")};
    std::mt19937_64 rng(20261121);
    int accepted = 0, refused = 0;
    for (int i = 0; i < 3000; ++i) {
        const std::string text = mutate(seeds[i % 3], rng);
        const auto outcome = shatter::test::checkObjInput(text);
        ASSERT_NE(outcome, shatter::test::FuzzOutcome::Bug) << "input #" << i << ":\n" << text;
        (outcome == shatter::test::FuzzOutcome::Accepted ? accepted : refused)++;
    }
    // Both paths must really be exercised, or the mutations are too weak or too strong.
    EXPECT_GT(accepted, 100);
    EXPECT_GT(refused, 100);
}
