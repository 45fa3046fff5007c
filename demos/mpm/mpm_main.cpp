// shatter-mpm: run a 2D crack scene file. See MpmProgram.h.
#include "demos/mpm/MpmProgram.h"
#include "demos/mpm/OpenMpWait.h"

#include <csignal>
#include <iostream>
#include <unistd.h>

int main(int argc, char** argv) {
    shatter::mpm::demo::boundOpenMpSpinning(argv);
    // Piped into `head`, the program must end with an exit code, not die of SIGPIPE.
    std::signal(SIGPIPE, SIG_IGN);
    const std::vector<std::string> args(argv + 1, argv + argc);
    return shatter::mpm::demo::runMpmProgram(args, std::cout, std::cerr, isatty(STDERR_FILENO) == 1);
}
