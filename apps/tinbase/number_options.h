// The command line's numbers, checked once for every command: each option or positional that
// CLI11 reads as a floating-point number (its type name FLOAT) refuses text that is not one
// decimal number, NaN, infinity and values beyond 1e15 (core/base/number_text.h), and each that
// it reads as an integer refuses text that is not a whole number or overflows 64 bits, before any
// handler runs, naming the option.
// Not thread-safe: call once, after every command is registered and before parsing.
#pragma once

#include <CLI/CLI.hpp>

namespace tinbase::cli {

// Adds the checks to every floating-point and integer option of `app` and of its subcommands, at
// any depth.
void CheckNumberOptions(CLI::App& app);

}  // namespace tinbase::cli
