// CTest runs two test programs at once on the two cores (ctest -j2); OpenMP teams of two
// threads in each would then wait on each other's descheduled threads at every barrier
// and run many times slower. The tests therefore default to one thread; the tests of the
// parallel paths (determinism across thread counts) ask for two explicitly.
#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

class SingleThread : public ::testing::Environment {
public:
    void SetUp() override {
#ifdef _OPENMP
        omp_set_num_threads(1);
#endif
    }
};

[[maybe_unused]] ::testing::Environment* const kSingleThread = ::testing::AddGlobalTestEnvironment(new SingleThread);

} // namespace
