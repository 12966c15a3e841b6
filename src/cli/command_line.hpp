#pragma once
// The command line as the user typed it: quantities read with their units and refused at
// their place on the line, and mistyped commands and options answered with the nearest.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/model/quantity_reader.hpp"

namespace ccomp::cli {

/// Keeps argv for positioned usage errors (main calls it once, before parsing).
void remember_command_line(int argc, const char* const* argv);

/// A usage error pointing at `value` of `option` on the command line ("command line:1:COL:
/// error: ...", the line, a caret under the value); unpositioned when it is not found there.
[[nodiscard]] Error usage_error_at(std::string_view option, std::string_view value, const std::string& message);

/// A CLI11 transform for `option`: its text read by model::read_quantity under `rule`
/// ("1um", "0.01deg", a bare number in rule.unit) and replaced by the number in rule.unit.
/// A refusal is a ccomp::Error (usage) at the value's place.
[[nodiscard]] CLI::Validator quantity(const model::QuantityRule& rule, std::string option);

/// `text` (one --at or --work-offset item's value) read under `rule`, refused at the place of
/// `whole` (the option's value as typed) on the command line.
[[nodiscard]] double quantity_in(std::string_view text, const model::QuantityRule& rule, std::string_view option,
                                 std::string_view whole);

/// After CLI11 refused the command line: a mistyped command or an option `app` (or the
/// command named) lacks, as an error with the nearest known name; nothing when it is not that.
[[nodiscard]] std::optional<Error> mistyped(const CLI::App& app, int argc, const char* const* argv);

/// Before the main job: its first input names no file and is a word, not a path (as a
/// mistyped command is: `ccomp chek data.csv`): refused, with the nearest command.
void refuse_mistyped_command(const CLI::App& app, const std::vector<std::string>& inputs);

}  // namespace ccomp::cli
