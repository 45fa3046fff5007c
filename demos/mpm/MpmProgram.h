#pragma once
// shatter-mpm SCENE.json [--out DIR] [--frames N] [--seed S] [--threads T] [--quiet]
//                        [--png-every N] [--png-size WxH]
//                        [--max-particles N] [--max-substeps N] [--max-memory GB]
// Runs a 2D crack scene and writes tips.csv, per-frame particle and crack CSV files and
// per-frame PNG pictures (see MpmOutput.h, MpmPicture.h). The scene's cost (particles, grid,
// memory, substeps) is estimated and printed before the run; beyond the limits (SceneBudget.h)
// it is an error naming the estimate and the option that raises the limit. Errors are printed as
// "shatter-mpm: error: ..." and give exit code 1.
#include <ostream>
#include <string>
#include <vector>

namespace shatter::mpm::demo {

// `args` excludes the program name. `err` gets the progress line only when `progressAllowed`
// (the real program passes true when stderr is a terminal).
int runMpmProgram(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progressAllowed);

} // namespace shatter::mpm::demo
