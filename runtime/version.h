// What `quantum --version` says: enough of the build to make the same binary again, or to tell
// two binaries apart in a bug report; and which of the engine's optional parts it has.
#pragma once

#include <string>

namespace quantum::runtime {

// "quantum 0.1.0 (commit 85e8be3, Release, -march=native, gcc 12.2.0, sanitizers off)": the
// project's version, the commit (engine_version(), as recordings and decision logs name it), the
// build type, whether it was built for this machine's CPU only, the compiler and the sanitizers.
std::string version_line();

// The parts of the engine a build may leave out, each with its packages (CMake's QUANTUM_WITH_*
// options, CONTRIBUTING.md). Code that reaches one is compiled under #if QUANTUM_WITH_<NAME>.
enum class Module { Tracking, Desk, Recognizer, Reference };

// "modules: tracking on, desk on, recognizer off, reference on": `quantum --version`'s second line.
std::string modules_line();

// What a command or an option of a module this build left out says, after its name: "this
// quantum was built without the speech recognizer (-DQUANTUM_WITH_RECOGNIZER=ON)".
std::string built_without(Module module);

}  // namespace quantum::runtime
