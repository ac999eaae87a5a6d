#include "interrupts.h"

#include <csignal>

namespace quantum::runtime {
namespace {

volatile std::sig_atomic_t asked = 0;

void ask_to_end(int signal) { asked = signal; }

}  // namespace

void end_matches_on_signals() {
  struct sigaction action {};
  action.sa_handler = ask_to_end;
  sigemptyset(&action.sa_mask);
  // SA_RESETHAND: the second signal finds the default action, which ends the process.
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int interrupting_signal() { return asked; }

}  // namespace quantum::runtime
