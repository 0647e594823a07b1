#include "uwscan/util/interrupt.h"

#include <gtest/gtest.h>

#include <csignal>

namespace uwscan {
namespace {

TEST(Interrupt, ASignalWithinTheScopeIsThrownAtTheNextCheck) {
  InterruptibleScope scope;
  EXPECT_NO_THROW(ThrowIfInterrupted());
  std::raise(SIGINT);  // the process goes on: only noted
  try {
    ThrowIfInterrupted();
    FAIL() << "not thrown";
  } catch (const Interrupted& e) {
    EXPECT_EQ(e.signal(), SIGINT);
    EXPECT_STREQ(e.what(), "interrupted by Ctrl-C");
  }
}

TEST(Interrupt, NestedScopesKeepTheHandlerUntilTheOutermostEnds) {
  InterruptibleScope outer;
  { InterruptibleScope inner; }  // a simulation within a demo, done
  std::raise(SIGTERM);
  EXPECT_THROW(ThrowIfInterrupted(), Interrupted);
}

TEST(Interrupt, ANewScopeStartsClear) {
  {
    InterruptibleScope scope;
    std::raise(SIGINT);
  }
  InterruptibleScope next;
  EXPECT_NO_THROW(ThrowIfInterrupted());
}

}  // namespace
}  // namespace uwscan
