#include "version.h"

#include <iterator>

#include "recording.h"

namespace quantum::runtime {

namespace {

struct ModuleInfo {
  const char* name;    // in --version
  const char* what;    // in built_without
  const char* option;  // CMake's
  bool built;
};
// In the order of enum class Module.
constexpr ModuleInfo kModules[] = {
    {"tracking", "tracking", "QUANTUM_WITH_TRACKING", QUANTUM_WITH_TRACKING},
    {"desk", "the desk", "QUANTUM_WITH_DESK", QUANTUM_WITH_DESK},
    {"recognizer", "the speech recognizer", "QUANTUM_WITH_RECOGNIZER", QUANTUM_WITH_RECOGNIZER},
    {"reference", "the Box2D reference backend", "QUANTUM_WITH_REFERENCE", QUANTUM_WITH_REFERENCE},
};

}  // namespace

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

std::string modules_line() {
  std::string line = "modules:";
  for (const ModuleInfo& m : kModules) line += std::string(&m == kModules ? " " : ", ") + m.name + (m.built ? " on" : " off");
  return line;
}

std::string built_without(Module module) {
  static_assert(std::size(kModules) == size_t(Module::Reference) + 1, "one entry per Module");
  const ModuleInfo& m = kModules[size_t(module)];
  return std::string("this quantum was built without ") + m.what + " (-D" + m.option + "=ON)";
}

}  // namespace quantum::runtime
