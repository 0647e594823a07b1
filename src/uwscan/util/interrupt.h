// Ctrl-C and SIGTERM during a long job. While an InterruptibleScope exists
// (the job functions that loop over frames make one), the signal is only
// noted, and the job's loop calls ThrowIfInterrupted() once per frame: the
// job unwinds as from any error, its temporary files and the folders it
// made are removed, and nothing is left under the final names. Outside a
// scope, and at a second signal, the process stops at once as usual.
#pragma once

#include "uwscan/util/error.h"

namespace uwscan {

// Thrown by ThrowIfInterrupted(); the CLI exits with 128 + signal(). A job
// that leaves complete outputs of an earlier stage behind says so in
// `outcome` ("R holds pass 1's outputs"), appended to the message.
class Interrupted : public Error {
 public:
  explicit Interrupted(int signal, const std::string& outcome = "");
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Scopes nest (a demo simulates, then reconstructs); the outermost one
// installs the handler and restores the default one. Main thread only.
class InterruptibleScope {
 public:
  InterruptibleScope();
  ~InterruptibleScope();
  InterruptibleScope(const InterruptibleScope&) = delete;
  InterruptibleScope& operator=(const InterruptibleScope&) = delete;
};

// Throws Interrupted if a signal arrived within the scope.
void ThrowIfInterrupted();

}  // namespace uwscan
