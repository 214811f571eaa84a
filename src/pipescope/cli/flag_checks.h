#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace pipescope {

// A number flag's check: finite and within [low, high] (open at `low` when `low_open`), with
// the bounds printed as short numbers. CLI11's PositiveNumber lets "nan" and "inf" through.
CLI::Validator FiniteRange(double low, double high, bool low_open = false);

// Finite and > 0, at most `high`.
inline CLI::Validator FinitePositive(double high = 1e12) { return FiniteRange(0.0, high, true); }
// Finite and >= 0, at most `high`.
inline CLI::Validator FiniteNonNegative(double high = 1e12) { return FiniteRange(0.0, high); }

}  // namespace pipescope
