#include "uwscan/util/interrupt.h"

#include <csignal>
#include <string>

namespace uwscan {
namespace {

volatile std::sig_atomic_t received = 0;
int depth = 0;

extern "C" void OnSignal(int signal) {
  received = signal;
  std::signal(signal, SIG_DFL);  // a second one stops the process at once
}

}  // namespace

Interrupted::Interrupted(int signal)
    : Error(std::string("interrupted by ") + (signal == SIGTERM ? "SIGTERM" : "Ctrl-C")),
      signal_(signal) {}

InterruptibleScope::InterruptibleScope() {
  if (depth++ > 0) return;
  received = 0;
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
}

InterruptibleScope::~InterruptibleScope() {
  if (--depth > 0) return;
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

void ThrowIfInterrupted() {
  if (const int signal = received) throw Interrupted(signal);
}

}  // namespace uwscan
