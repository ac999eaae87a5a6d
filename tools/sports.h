// `quantum sports`: every sport a name reaches (bindings/engine_paths.h), each with its players
// and the parameters its scripts read.
#pragma once

#include <iosfwd>

namespace quantum::tools {

// Writes the list to `out`; a sport that does not load is listed with its error. Returns how many
// did not load.
int list_sports(std::ostream& out);

}  // namespace quantum::tools
