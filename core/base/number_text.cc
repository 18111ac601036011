#include "core/base/number_text.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace tinbase {

std::optional<NumberProblem> CheckNumber(double value) {
  if (!std::isfinite(value)) return NumberProblem::kNotFinite;
  if (std::fabs(value) > kMaxMagnitude) return NumberProblem::kTooLarge;
  return std::nullopt;
}

NumberText ParseNumberText(std::string_view field) {
  NumberText out;
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, out.value);
  if (field.empty() || ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    out.problem = NumberProblem::kNotANumber;
  } else if (ec == std::errc::result_out_of_range) {
    // from_chars leaves the value unset out of range; strtod says which way it fell: an
    // underflow (1e-400) is a harmless zero, an overflow (4e400) is not finite.
    out.value = std::strtod(std::string(field).c_str(), nullptr);
    out.problem = CheckNumber(out.value);
  } else {
    out.problem = CheckNumber(out.value);
  }
  return out;
}

std::string DescribeNumberProblem(NumberProblem problem) {
  switch (problem) {
    case NumberProblem::kNotANumber:
      return "is not a number";
    case NumberProblem::kNotFinite:
      return "is not finite";
    case NumberProblem::kTooLarge:
      break;
  }
  return "is larger in magnitude than 1e15";
}

Result<double> UsableNumber(double value, const std::string& what) {
  if (auto problem = CheckNumber(value)) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);
    return Status::InvalidArgument(what + " " + text + " " + DescribeNumberProblem(*problem));
  }
  return value;
}

Result<double> ParseUsableNumber(std::string_view field, const std::string& what) {
  const NumberText n = ParseNumberText(field);
  if (n.problem)
    return Status::InvalidArgument(what + " '" + std::string(field) + "' " +
                                   DescribeNumberProblem(*n.problem));
  return n.value;
}

}  // namespace tinbase
