#include "solvers/solver_params.h"

#include <gtest/gtest.h>

namespace gistream {
namespace solver_params_test {

SolverDescription Direct() {
  SolverDescription d;
  d.name = "direct";
  d.params = {
      {"area_samples", ParamType::kInt, "16", 1, 1024, {}, "samples per area light"},
      {"exposure", ParamType::kFloat, "0", -20, 20, {}, "stops"},
      {"shadows", ParamType::kBool, "true", 0, 0, {}, "shadow maps on/off"},
      {"filter", ParamType::kEnum, "pcf", 0, 0, {"none", "pcf", "pcss"}, "shadow filter"},
  };
  return d;
}

void ExpectInvalid(const std::map<std::string, std::string>& given, const std::string& text) {
  const absl::StatusOr<ParamSet> set = ValidateParams(Direct(), given);
  ASSERT_FALSE(set.ok());
  EXPECT_EQ(set.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(set.status().message().find(text), std::string::npos) << set.status().message();
}

TEST(SolverParams, DefaultsFillWhatIsNotGiven) {
  const absl::StatusOr<ParamSet> set = ValidateParams(Direct(), {{"area_samples", "64"}});
  ASSERT_TRUE(set.ok()) << set.status();
  EXPECT_EQ(set->GetInt("area_samples"), 64);
  EXPECT_DOUBLE_EQ(set->GetFloat("exposure"), 0.0);
  EXPECT_TRUE(set->GetBool("shadows"));
  EXPECT_EQ(set->GetString("filter"), "pcf");
  EXPECT_EQ(set->Key(), "area_samples=64;exposure=0;filter=pcf;shadows=true");
}

TEST(SolverParams, CanonicalKeyIgnoresSpelling) {
  const auto a = ValidateParams(Direct(), {{"shadows", "1"}, {"exposure", "0.50"}});
  const auto b = ValidateParams(Direct(), {{"shadows", "true"}, {"exposure", "5e-1"}});
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->Key(), b->Key());
  EXPECT_DOUBLE_EQ(a->GetFloat("exposure"), 0.5);
}

TEST(SolverParams, BoolsAcceptTrueFalseOneZero) {
  for (const char* v : {"true", "1"}) {
    EXPECT_TRUE(ValidateParams(Direct(), {{"shadows", v}})->GetBool("shadows")) << v;
  }
  for (const char* v : {"false", "0"}) {
    EXPECT_FALSE(ValidateParams(Direct(), {{"shadows", v}})->GetBool("shadows")) << v;
  }
  ExpectInvalid({{"shadows", "yes"}}, "params.shadows: 'yes' is not a boolean");
}

TEST(SolverParams, IntOutOfRange) {
  ExpectInvalid({{"area_samples", "0"}}, "params.area_samples: 0 is out of range [1, 1024]");
  ExpectInvalid({{"area_samples", "1025"}}, "params.area_samples: 1025 is out of range");
}

TEST(SolverParams, IntParsesStrictly) {
  for (const char* v : {"", "12x", " 12", "12 ", "+12", "1.5", "0x10", "99999999999999999999"}) {
    ExpectInvalid({{"area_samples", v}}, "params.area_samples:");
  }
}

TEST(SolverParams, FloatsRejectNanAndInf) {
  ExpectInvalid({{"exposure", "nan"}}, "params.exposure: 'nan' is not finite");
  ExpectInvalid({{"exposure", "inf"}}, "params.exposure: 'inf' is not finite");
  ExpectInvalid({{"exposure", "-inf"}}, "params.exposure:");
  ExpectInvalid({{"exposure", "abc"}}, "params.exposure: 'abc' is not a number");
  ExpectInvalid({{"exposure", "21"}}, "params.exposure: 21 is out of range [-20, 20]");
}

TEST(SolverParams, EnumMustBeAChoice) {
  EXPECT_EQ(ValidateParams(Direct(), {{"filter", "pcss"}})->GetString("filter"), "pcss");
  ExpectInvalid({{"filter", "PCF"}}, "params.filter: 'PCF' is not one of none, pcf, pcss");
}

TEST(SolverParams, UnknownNameListsTheKnownOnes) {
  ExpectInvalid({{"foo", "1"}},
                "params.foo: unknown parameter of solver 'direct' (known: area_samples, "
                "exposure, shadows, filter)");
}

TEST(SolverParams, BadDefaultIsReported) {
  SolverDescription d = Direct();
  d.params[0].default_value = "0";
  const auto set = ValidateParams(d, {});
  ASSERT_FALSE(set.ok());
  EXPECT_NE(set.status().message().find("params.area_samples (default)"), std::string::npos);
}

}  // namespace solver_params_test
}  // namespace gistream
