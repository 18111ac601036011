// The command line's numbers, checked once for every command: each option or positional that
// CLI11 reads as a floating-point number (its type name FLOAT) refuses NaN, infinity and values
// beyond 1e15 (core/base/number_text.h) before any handler runs, naming the option.
// Not thread-safe: call once, after every command is registered and before parsing.
#pragma once

#include <CLI/CLI.hpp>

namespace tinbase::cli {

// Adds the check to every floating-point option of `app` and of its subcommands, at any depth.
void CheckNumberOptions(CLI::App& app);

}  // namespace tinbase::cli
