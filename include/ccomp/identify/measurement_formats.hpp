#pragma once
// The kinds of measurement file ccomp reads, each recognised by its content: the CSV
// contract itself, and what instruments and their software write (a Renishaw laser's .rtl
// text, a one-axis table from a spreadsheet or a rotary calibrator). Each is one
// descriptor; a new format is one new file and its line in the list (measurement_formats.cpp).
#include <cstddef>
#include <istream>
#include <span>
#include <string>
#include <string_view>

#include "ccomp/identify/measurements.hpp"

namespace ccomp::identify::io {

/// How much of a file's start recognising its format looks at.
inline constexpr std::size_t kDetectBytes = 4096;

struct MeasurementFormat {
  std::string_view name;         ///< "csv", "renishaw-rtl", "axis-table"
  std::string_view description;  ///< for the message when no format matches
  /// Whether a file starting with `head` (its first kDetectBytes) is of this format.
  bool (*detect)(std::string_view head) = nullptr;
  /// Reads the file into `into`; throws ccomp::Error (data) at its file, line and column.
  void (*read)(std::istream& in, const std::string& name, const model::MachineModel& model,
               const ReadOptions& options, MeasurementSet& into) = nullptr;
};

/// Every format, in the order they are tried (the more specific first).
[[nodiscard]] std::span<const MeasurementFormat> measurement_formats();

/// The format of the file `name` starting with `head`; throws ccomp::Error (data) listing the
/// formats when none recognises it.
[[nodiscard]] const MeasurementFormat& detect_format(std::string_view head, const std::string& name);

// The formats' readers (one file each under src/identify/io/).
[[nodiscard]] const MeasurementFormat& contract_csv_format();
[[nodiscard]] const MeasurementFormat& renishaw_rtl_format();
[[nodiscard]] const MeasurementFormat& axis_table_format();

/// A row's program coordinates (with the tool length on Z) as machine positions in `frame`.
void to_machine(model::ChainQ& q, const ResolvedFrame& frame);
/// A file's observations from `first` on, read in program coordinates, placed in machine
/// positions; `frame` recorded as the file's (MeasurementSet::frames), and an origin nobody
/// gave said where a rotary axis turns.
void place_in_machine(MeasurementSet& set, std::size_t first, const ResolvedFrame& frame,
                      const model::MachineModel& model, const std::string& name);

/// The contract CSV's reader (identify/measurements.cpp).
void read_contract(std::istream& in, const std::string& name, const model::MachineModel& model,
                   const ReadOptions& options, MeasurementSet& into);

}  // namespace ccomp::identify::io
