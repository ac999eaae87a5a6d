// The field loader on any field.lua: it loads, or refuses with a FieldError; it never crashes,
// hangs or lets another exception out.
#include "field_loader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = quantum::fuzz::scratch() / "field.lua";
  quantum::fuzz::write_file(file, data, size);
  try {
    quantum::lua::load_field(file.string());
  } catch (const quantum::FieldError&) {
  }
  return 0;
}
