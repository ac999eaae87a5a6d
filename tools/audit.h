// `quantum audit`: checks decision logs (docs/decisions.md, version 2) from the file alone: every
// draw's arithmetic, chances, uniform number and outcome, each realized outcome against its
// events log, then whether the outcomes of all the draws pooled follow their chances.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace quantum::tools {

// `files`: decision logs and events logs (--events) in any mix, told apart by their content; the
// first events log goes with the first decision log, and so on. Prints the tests with their
// figures and thresholds to `out`, ending with "audit: passed" (returns 0) or "audit: FAILED" and
// the first violation, naming its file, line and match time (returns 1). A file that cannot be
// read, is not a log or is a version-1 decision log is told on `err` (returns 2). With
// `progress`, a line on `err` counts the draws read.
int audit(const std::vector<std::string>& files, std::ostream& out, std::ostream& err, bool progress);

}  // namespace quantum::tools
