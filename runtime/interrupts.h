// Ctrl-C (SIGINT) and SIGTERM at a venue end the match as its time limit would: the frame under
// way completes, every file the match writes is completed, and the transcript says how the match
// stood. A second signal ends the process at once, as without this.
#pragma once

namespace quantum::runtime {

// From now on SIGINT and SIGTERM end the running sessions (Session::frame returns false) instead
// of the process: called once a match runs, so that a command still starting (or stuck opening a
// device) ends as before. Only for commands whose every loop asks interrupting_signal().
void end_matches_on_signals();
// The signal that asked the matches to end, or 0.
int interrupting_signal();

}  // namespace quantum::runtime
