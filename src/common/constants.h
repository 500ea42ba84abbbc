// Constants every layer uses, defined once: no file defines its own (a
// unity build compiles a target's files as one; docs/architecture.md,
// "Build time").
#pragma once

#include <limits>
#include <numbers>

namespace camdyn {

inline constexpr double kPi = std::numbers::pi;                // [rad]
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;       // [rad]
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;  // [deg/rad]
inline constexpr double kDegToRad = std::numbers::pi / 180.0;  // [rad/deg]
inline constexpr double kMm = 1e3;                             // [mm/m]
inline constexpr double kSecondsPerMinute = 60.0;              // [s/min]: revolutions per second = rpm / 60
/// A cam speed in rpm times this is the speed in rad/s.
inline constexpr double kRadPerSecondPerRpm = 2.0 * std::numbers::pi / 60.0;  // [(rad/s)/rpm]
inline constexpr double kInf = std::numeric_limits<double>::infinity();
/// A point of a plotted series where its line breaks (gnuplot leaves NaN out).
inline constexpr double kBreak = std::numeric_limits<double>::quiet_NaN();

}  // namespace camdyn
