// The time series' columns (timeseries.csv, the API's Columns, the Python
// module's TIMESERIES_UNITS and TRAIN_COLUMN_UNITS): one table of the columns
// every run has, in order, with their units, and one table of a follower
// train's column suffixes (`<body>_position`, ...) with theirs. Whatever names
// a column or gives its unit reads them, so a column is added in one place
// (docs/config.md, "Outputs of `simulate`", lists them for users).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace camdyn {

/// A column every run has.
struct SeriesColumn {
  const char* name;
  const char* unit;      ///< for a translating follower (ASCII: "m/s^2")
  const char* arm_unit;  ///< for an oscillating arm: q's columns are angles
};

/// In the order of TimeSeries::columns().
inline constexpr std::array<SeriesColumn, 12> kSeriesColumns{{
    {"time", "s", "s"},
    {"cam_angle_deg", "deg", "deg"},
    {"follower_position", "m", "rad"},
    {"follower_velocity", "m/s", "rad/s"},
    {"follower_acceleration", "m/s^2", "rad/s^2"},
    {"kinematic_position", "m", "rad"},
    {"gap", "m", "m"},
    {"contact_force", "N", "N"},
    {"friction_force", "N", "N"},
    {"energy_residual", "-", "-"},
    {"contact_offset", "m", "m"},
    {"cam_speed_rpm", "rpm", "rpm"},
}};

/// A train body's columns, by their suffix after the body's name.
enum class TrainColumn { position, velocity, link_force, seat_force, stop_force, spring_force, gas_force };

/// In the order of TrainColumn.
struct TrainColumnSuffix {
  const char* suffix;
  const char* unit;      ///< a train body's coordinate is a length even after an arm
  const char* arm_unit;  ///< the follower's own seat, stop and spring force on an arm act along its angle
};

inline constexpr std::array<TrainColumnSuffix, 7> kTrainColumns{{
    {"_position", "m", "m"},
    {"_velocity", "m/s", "m/s"},
    {"_link_force", "N", "N"},
    {"_seat_force", "N", "N m"},
    {"_stop_force", "N", "N m"},
    {"_spring_force", "N", "N m"},
    {"_gas_force", "N", "N"},
}};

/// `<body><suffix>`: the name of a train body's column.
inline std::string train_column_name(std::string_view body, TrainColumn c) {
  return std::string(body) + kTrainColumns[static_cast<std::size_t>(c)].suffix;
}

/// The train column whose suffix `name` ends in, after a body's name (the
/// longest suffix that fits), or null.
inline const TrainColumnSuffix* train_column_of(std::string_view name) {
  const TrainColumnSuffix* best = nullptr;
  for (const TrainColumnSuffix& c : kTrainColumns) {
    const std::string_view suffix = c.suffix;
    if (name.size() > suffix.size() && name.ends_with(suffix) &&
        (!best || suffix.size() > std::string_view(best->suffix).size()))
      best = &c;
  }
  return best;
}

/// The unit of the column `name`: a column every run has, else a train
/// column by its suffix (the longest that fits, with a body's name before
/// it); "" for any other name. `oscillating`: the follower is an arm (its
/// coordinate's columns in rad, its own seat, stop and spring forces in
/// N m; a train body's columns keep theirs).
inline std::string series_column_unit(std::string_view name, bool oscillating = false) {
  for (const SeriesColumn& c : kSeriesColumns)
    if (name == c.name) return oscillating ? c.arm_unit : c.unit;
  const TrainColumnSuffix* best = train_column_of(name);
  if (!best) return "";
  const bool follower = name.substr(0, name.size() - std::string_view(best->suffix).size()) == "follower";
  return oscillating && follower ? best->arm_unit : best->unit;
}

}  // namespace camdyn
