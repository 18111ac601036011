#include "apps/tinbase/number_options.h"

#include <charconv>
#include <cstdint>
#include <string>

#include "core/base/number_text.h"

namespace tinbase::cli {

namespace {

// The whole text must be one decimal number: CLI11's own conversion (strtod) would also take
// blanks around it, hexadecimal ("0x10") and an empty text (as 0).
CLI::Validator UsableNumberValidator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const NumberText n = ParseNumberText(text);
        if (!n.problem) return {};
        return "'" + text + "' " + DescribeNumberProblem(*n.problem);
      },
      "", "usable number");
}

// A whole number in range: CLI11's conversion turns 99999999999999999999 into the largest
// int64 without a word, and reads "0x10" as 16.
CLI::Validator WholeNumberValidator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::string_view field = text;
        if (!field.empty() && field.front() == '+') field.remove_prefix(1);
        int64_t value = 0;
        const char* end = field.data() + field.size();
        const auto [ptr, ec] = std::from_chars(field.data(), end, value);
        if (ec == std::errc::result_out_of_range) return "'" + text + "' is out of range";
        if (field.empty() || ec != std::errc() || ptr != end)
          return "'" + text + "' is not a whole number";
        return {};
      },
      "", "whole number");
}

bool ReadsFloats(const CLI::Option& option) {
  return option.get_type_name().find("FLOAT") != std::string::npos;
}

bool ReadsIntegers(const CLI::Option& option) {
  const std::string type = option.get_type_name();
  return type.find("INT") != std::string::npos && option.get_expected_min() > 0;
}

}  // namespace

void CheckNumberOptions(CLI::App& app) {
  for (CLI::Option* option : app.get_options())
    if (ReadsFloats(*option))
      option->check(UsableNumberValidator());
    else if (ReadsIntegers(*option))
      option->check(WholeNumberValidator());
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    CheckNumberOptions(*sub);
}

}  // namespace tinbase::cli
