#include "uwscan/util/interrupt.h"

#include <csignal>
#include <string>

namespace uwscan {
namespace {

volatile std::sig_atomic_t received = 0;
int depth = 0;
using Handler = void (*)(int);
Handler previous_int = SIG_DFL, previous_term = SIG_DFL;

extern "C" void OnSignal(int signal) {
  received = signal;
  std::signal(signal, SIG_DFL);  // a second one stops the process at once
}

// A signal the process was started with ignored (nohup, a background job
// of a script) stays ignored.
Handler Install(int signal) {
  const Handler previous = std::signal(signal, OnSignal);
  if (previous == SIG_IGN) std::signal(signal, SIG_IGN);
  return previous == SIG_ERR ? SIG_DFL : previous;
}

}  // namespace

Interrupted::Interrupted(int signal, const std::string& outcome)
    : Error(std::string("interrupted by ") + (signal == SIGTERM ? "SIGTERM" : "Ctrl-C") +
            (outcome.empty() ? "" : ": " + outcome)),
      signal_(signal) {}

InterruptibleScope::InterruptibleScope() {
  if (depth++ > 0) return;
  received = 0;
  previous_int = Install(SIGINT);
  previous_term = Install(SIGTERM);
}

InterruptibleScope::~InterruptibleScope() {
  if (--depth > 0) return;
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
}

void ThrowIfInterrupted() {
  if (const int signal = received) throw Interrupted(signal);
}

}  // namespace uwscan
