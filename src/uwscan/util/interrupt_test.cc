#include "uwscan/util/interrupt.h"

#include <gtest/gtest.h>

#include <csignal>

namespace uwscan {
namespace {

class Interrupt : public ::testing::Test {
 protected:
  // As from a terminal (a test runner may have started us with them ignored).
  void SetUp() override {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
  }
};

TEST_F(Interrupt, ASignalWithinTheScopeIsThrownAtTheNextCheck) {
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

TEST_F(Interrupt, NestedScopesKeepTheHandlerUntilTheOutermostEnds) {
  InterruptibleScope outer;
  { InterruptibleScope inner; }  // a simulation within a demo, done
  std::raise(SIGTERM);
  EXPECT_THROW(ThrowIfInterrupted(), Interrupted);
}

TEST_F(Interrupt, ANewScopeStartsClear) {
  {
    InterruptibleScope scope;
    std::raise(SIGINT);
  }
  InterruptibleScope next;
  EXPECT_NO_THROW(ThrowIfInterrupted());
}

// Started with Ctrl-C ignored (nohup, a script's background job): it stays
// ignored, within the scope and after it.
TEST_F(Interrupt, AnIgnoredSignalStaysIgnored) {
  std::signal(SIGINT, SIG_IGN);
  {
    InterruptibleScope scope;
    std::raise(SIGINT);
    EXPECT_NO_THROW(ThrowIfInterrupted());
  }
  EXPECT_EQ(std::signal(SIGINT, SIG_DFL), SIG_IGN);
}

}  // namespace
}  // namespace uwscan
