#include "apps/tinbase/number_options.h"

#include <string>

#include "core/base/number_text.h"

namespace tinbase::cli {

namespace {

// Text that is no number at all is left to CLI11's conversion, which names the option too.
CLI::Validator UsableNumberValidator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const NumberText n = ParseNumberText(text);
        if (!n.problem || *n.problem == NumberProblem::kNotANumber) return {};
        return "'" + text + "' " + DescribeNumberProblem(*n.problem);
      },
      "", "usable number");
}

bool ReadsFloats(const CLI::Option& option) {
  return option.get_type_name().find("FLOAT") != std::string::npos;
}

}  // namespace

void CheckNumberOptions(CLI::App& app) {
  for (CLI::Option* option : app.get_options())
    if (ReadsFloats(*option)) option->check(UsableNumberValidator());
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    CheckNumberOptions(*sub);
}

}  // namespace tinbase::cli
