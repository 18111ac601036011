// Numbers from outside (command-line values, text files, request parameters): the one place
// that says what a usable number is.
//
// A usable number is finite and no larger in magnitude than kMaxMagnitude. NaN and infinity
// carry no position or elevation, and a value beyond 1e15 is always a mistake for a coordinate,
// a level, a length or an area in any CRS unit (the Earth is 4e7 m round; 1e15 squared still
// fits a double with room for the products the geometry forms). Every parser of outside input
// checks its numbers here, so the rule and its words are the same everywhere.
// Thread-safe: pure functions.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/base/status.h"

namespace tinbase {

inline constexpr double kMaxMagnitude = 1e15;

// Why a field is not a usable number; nullopt when it is one.
enum class NumberProblem { kNotANumber, kNotFinite, kTooLarge };

struct NumberText {
  double value = 0;
  std::optional<NumberProblem> problem;  // nullopt: `value` is usable
};

// The whole of `field` as one number (a leading '+' allowed, no blanks). A value that overflows
// a double reads as not finite.
NumberText ParseNumberText(std::string_view field);

// The problem in words: "is not a number", "is not finite", "is larger in magnitude than 1e15".
std::string DescribeNumberProblem(NumberProblem problem);

// nullopt when `value` is usable, else its problem.
std::optional<NumberProblem> CheckNumber(double value);

// `value` when usable; InvalidArgument "<what> <value> <problem>" otherwise.
Result<double> UsableNumber(double value, const std::string& what);

// The number in `field`; InvalidArgument "<what> '<field>' <problem>" otherwise.
Result<double> ParseUsableNumber(std::string_view field, const std::string& what);

}  // namespace tinbase
