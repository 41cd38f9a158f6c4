// doctest main shared by every test executable: runs the tests, then fails the process if the
// Vulkan validation layer reported any error, naming the test case during which it happened.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <iostream>
#include <mutex>

#include "test_context.h"

namespace {

int g_cases_with_validation_errors = 0;

struct ValidationListener : doctest::IReporter {
  explicit ValidationListener(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats&) override {}
  void test_case_start(const doctest::TestCaseData& tc) override { name_ = tc.m_name; }
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats&) override {
    if (!s4d::test::context_created()) return;
    auto messages = s4d::test::context().take_validation_messages();
    if (messages.empty()) return;
    ++g_cases_with_validation_errors;
    std::cerr << "VALIDATION ERRORS in test case '" << name_ << "':\n";
    for (const auto& m : messages) std::cerr << "  " << m << "\n";
  }
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}

  std::string name_;
};

REGISTER_LISTENER("validation", 1, ValidationListener);

}  // namespace

int main(int argc, char** argv) {
  doctest::Context runner(argc, argv);
  const int result = runner.run();
  s4d::test::release_context();
  if (runner.shouldExit()) return result;
  if (g_cases_with_validation_errors > 0) {
    std::cerr << g_cases_with_validation_errors << " test case(s) produced Vulkan validation errors\n";
    return result ? result : 1;
  }
  return result;
}
