// The test helper expect_allclose (tests/support/expect_allclose.h) must fail where it should:
// non-finite values first, each element against atol + rtol * |expected|, the worst one named.
#include <doctest/doctest.h>

#include <limits>
#include <string>
#include <vector>

#include "expect_allclose.h"

namespace {

using s4d::test::allclose_report;
using s4d::test::AllcloseReport;
using s4d::test::Tolerance;

bool mentions(const AllcloseReport& r, const std::string& part) { return r.message.find(part) != std::string::npos; }

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace

TEST_CASE("allclose passes equal arrays and differences inside atol + rtol * |expected|") {
  const std::vector<double> want = {0.0, 1.0, -100.0};
  CHECK(allclose_report(std::vector<float>{0.0f, 1.0f, -100.0f}, want, {}, "x").ok);
  // |diff| 1e-6 at 0 needs atol; 1e-3 at -100 is inside rtol 1e-5 * 100.
  CHECK(allclose_report(std::vector<float>{1e-6f, 1.0f, -100.001f}, want, {.atol = 2e-6, .rtol = 1e-5}, "x").ok);
  CHECK_FALSE(allclose_report(std::vector<float>{1e-6f, 1.0f, -100.001f}, want, {.atol = 2e-6, .rtol = 0}, "x").ok);
}

TEST_CASE("allclose fails a NaN or infinity where a finite value is expected, naming the index") {
  const std::vector<double> want = {1.0, 2.0, 3.0};
  const AllcloseReport nan = allclose_report(std::vector<float>{1.0f, 2.0f, kNan}, want, {.atol = 1e30}, "v_means");
  CHECK_FALSE(nan.ok);
  CHECK(mentions(nan, "v_means: [2] is nan, expected 3"));
  const AllcloseReport inf = allclose_report(std::vector<float>{1.0f, -kInf, 3.0f}, want, {.atol = 1e30}, "rgb");
  CHECK_FALSE(inf.ok);
  CHECK(mentions(inf, "rgb: [1] is -inf"));
}

TEST_CASE("allclose requires a non-finite expected value exactly: the same infinity, or NaN") {
  const std::vector<double> want = {kInf, std::numeric_limits<double>::quiet_NaN()};
  CHECK(allclose_report(std::vector<float>{kInf, kNan}, want, {}, "p").ok);
  CHECK_FALSE(allclose_report(std::vector<float>{3e38f, kNan}, want, {.atol = 1e38}, "p").ok);
  CHECK_FALSE(allclose_report(std::vector<float>{-kInf, kNan}, want, {}, "p").ok);
  CHECK_FALSE(allclose_report(std::vector<float>{kInf, 0.0f}, want, {.atol = 1e38}, "p").ok);
}

TEST_CASE("allclose names the worst element by its excess over its own tolerance, with the tolerance") {
  // [1] is off by 0.5 against a tolerance of 1.0 + 0.1 (fine); [2] by 0.02 against 0.01 (twice
  // over); [3] by 0.05 against 0.01 (five times over: the worst, though [1]'s difference is larger).
  const std::vector<float> got = {0.0f, 10.5f, 0.02f, -0.05f};
  const std::vector<double> want = {0.0, 10.0, 0.0, 0.0};
  const AllcloseReport r = allclose_report(got, want, {.atol = 0.01, .rtol = 0.1}, "planes");
  CHECK_FALSE(r.ok);
  CHECK(mentions(r, "planes: 2 of 4 elements outside atol 0.01 + rtol 0.1 * |expected|"));
  CHECK(mentions(r, "worst [3] -0.0500000007 vs 0"));
  CHECK(mentions(r, "\n  [2] "));
}

TEST_CASE("allclose refuses arrays of different sizes and compares double with double") {
  const AllcloseReport r = allclose_report(std::vector<double>{1.0}, std::vector<double>{1.0, 2.0}, {}, "sh");
  CHECK_FALSE(r.ok);
  CHECK(mentions(r, "sh: 1 elements, expected 2"));
  CHECK(allclose_report(std::vector<double>{1.0 + 1e-12}, std::vector<double>{1.0}, {.rtol = 1e-11}, "d").ok);
  CHECK_FALSE(allclose_report(std::vector<double>{1.0 + 1e-10}, std::vector<double>{1.0}, {.rtol = 1e-11}, "d").ok);
}

TEST_CASE("allclose's of_largest scales atol by the largest |expected|, and the report says so") {
  const std::vector<double> want = {1000.0, 0.0, -2.0};
  // 0.05 off at 0: inside 1e-4 x 1000 = 0.1, outside 1e-5 x 1000.
  CHECK(allclose_report(std::vector<float>{1000.0f, 0.05f, -2.0f}, want, {.of_largest = 1e-4}, "v").ok);
  const AllcloseReport r = allclose_report(std::vector<float>{1000.0f, 0.05f, -2.0f}, want, {.of_largest = 1e-5}, "v");
  CHECK_FALSE(r.ok);
  CHECK(mentions(r, "v: 1 of 3 elements outside atol 0 + 1e-05 * largest |expected| 1000"));
  CHECK(mentions(r, "worst [1]"));
}
