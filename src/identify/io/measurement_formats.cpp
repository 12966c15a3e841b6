// The list of measurement formats, and recognising a file's. A new format is a file of its
// own beside this one and its line below.
#include "ccomp/identify/measurement_formats.hpp"

#include <fmt/format.h>

#include <array>

#include "ccomp/error.hpp"

namespace ccomp::identify::io {

std::span<const MeasurementFormat> measurement_formats() {
  // The contract last: it reads whatever no instrument's reader recognises, so that a CSV
  // with a column missing is told which, not that its format is unknown.
  static const std::array<MeasurementFormat, 3> formats{renishaw_rtl_format(), axis_table_format(),
                                                        contract_csv_format()};
  return formats;
}

const MeasurementFormat& detect_format(std::string_view head, const std::string& name) {
  // What users pass for a measurement file and no reader can take: said as what it is.
  if (head.starts_with("PK\x03\x04"))
    throw Error(ErrorKind::data, "a zip file (a spreadsheet's .xlsx or .ods?): save the sheet as CSV (commas, semicolons or tabs)",
                SourceLocation{name, 1, 1});
  if (head.find('\0') != std::string_view::npos)
    throw Error(ErrorKind::data, "a binary file (a NUL byte in its first 4 kB): measurement files are text",
                SourceLocation{name, 1, 1});
  for (const MeasurementFormat& f : measurement_formats())
    if (f.detect(head)) return f;
  std::string known;
  for (const MeasurementFormat& f : measurement_formats())
    known += fmt::format("\n  {}: {}", f.name, f.description);
  throw Error(ErrorKind::data, fmt::format("{}: not a measurement file ccomp reads; it reads:{}", name, known));
}

namespace {

bool detect_contract(std::string_view) { return true; }

}  // namespace

const MeasurementFormat& contract_csv_format() {
  static const MeasurementFormat format{
      "csv", "the measurement contract: a header with x,y,z and nx,ny,nz,d or dx,dy,dz (docs/identification.md)",
      detect_contract, read_contract};
  return format;
}

}  // namespace ccomp::identify::io
