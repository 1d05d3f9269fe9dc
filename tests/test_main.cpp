// The main of every doctest program. A run that executes no test case (every case skipped, e.g.
// the shared-model suite without ../shared, or filtered out) exits with test::kSkipExitCode so ctest
// reports it as Skipped (SKIP_RETURN_CODE), never as Passed.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "shared_models.h"

namespace {

int g_started = 0;     // test cases that ran
bool g_query = false;  // --help, --list-test-cases, --count...: nothing is meant to run

struct RunCounter : doctest::IReporter {
  explicit RunCounter(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override { g_query = true; }
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats&) override {}
  void test_case_start(const doctest::TestCaseData&) override { ++g_started; }
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats&) override {}
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}
};

}  // namespace

REGISTER_LISTENER("nurbsgl_run_counter", 1, RunCounter);

int main(int argc, char** argv) {
  doctest::Context context(argc, argv);
  const int rc = context.run();
  if (context.shouldExit() || g_query || rc != 0) return rc;
  return g_started == 0 ? test::kSkipExitCode : 0;
}
