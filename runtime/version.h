// What `quantum --version` says: enough of the build to make the same binary again, or to tell
// two binaries apart in a bug report.
#pragma once

#include <string>

namespace quantum::runtime {

// "quantum 0.1.0 (commit 85e8be3, Release, -march=native, gcc 12.2.0, sanitizers off)": the
// project's version, the commit (engine_version(), as recordings and decision logs name it), the
// build type, whether it was built for this machine's CPU only, the compiler and the sanitizers.
std::string version_line();

}  // namespace quantum::runtime
