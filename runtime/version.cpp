#include "version.h"

#include "recording.h"

namespace quantum::runtime {

std::string version_line() {
  // CMake's compiler ids, as the compilers call themselves.
  const std::string id = QUANTUM_COMPILER_ID;
  const std::string compiler = id == "GNU" ? "gcc" : id == "Clang" ? "clang" : id;
  const std::string build_type = QUANTUM_BUILD_TYPE;
  return std::string("quantum ") + QUANTUM_PROJECT_VERSION + " (commit " + engine_version() + ", " +
         (build_type.empty() ? "no build type" : build_type) + ", " +
         (QUANTUM_NATIVE ? "-march=native" : "portable") + ", " + compiler + " " + QUANTUM_COMPILER_VERSION +
         ", sanitizers " + (QUANTUM_SANITIZE ? "on" : "off") + ")";
}

}  // namespace quantum::runtime
