#include "command_line.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "ccomp/util/nearest_name.hpp"

namespace ccomp::cli {
namespace {

std::vector<std::string>& typed() {
  static std::vector<std::string> words;
  return words;
}

/// The words of the line as shown, the command's own name without its folder.
std::string shown_word(std::size_t i) {
  const std::string& w = typed()[i];
  return i == 0 ? std::filesystem::path(w).filename().string() : w;
}

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (!sub->get_name().empty()) names.push_back(sub->get_name());
  return names;
}

std::vector<std::string_view> views(const std::vector<std::string>& names) {
  return {names.begin(), names.end()};
}

/// Every long option name `app` takes ("--tolerance"), --help and --version included.
std::vector<std::string> long_options(const CLI::App& app) {
  std::vector<std::string> names{"--help", "--version"};
  for (const CLI::Option* o : app.get_options())
    for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
  return names;
}

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

void remember_command_line(int argc, const char* const* argv) {
  typed().assign(argv, argv + argc);
}

namespace {

/// A usage error with a caret under word `index` of the line, `offset` characters into it.
Error error_at_word(std::size_t index, std::size_t offset, const std::string& message) {
  std::string line;
  std::size_t column = 0;
  for (std::size_t i = 0; i < typed().size(); ++i) {
    if (!line.empty()) line += ' ';
    if (i == index) column = line.size() + offset + 1;
    line += shown_word(i);
  }
  if (column == 0) return Error(ErrorKind::usage, message);
  return Error(ErrorKind::usage, message, SourceLocation{"command line", 1, static_cast<std::uint32_t>(column)}, line);
}

}  // namespace

Error usage_error_at(std::string_view option, std::string_view value, const std::string& message) {
  const std::string joined = std::string(option) + "=";
  for (std::size_t i = 1; i < typed().size(); ++i) {
    const std::string& w = typed()[i];
    if (w == value && typed()[i - 1] == option) return error_at_word(i, 0, message);
    if (w.starts_with(joined) && std::string_view(w).substr(joined.size()) == value)
      return error_at_word(i, joined.size(), message);
  }
  return Error(ErrorKind::usage, message);
}

double quantity_in(std::string_view text, const model::QuantityRule& rule, std::string_view option,
                   std::string_view whole) {
  try {
    return model::read_quantity(text, rule, fmt::format("{} {}", option, whole));
  } catch (const Error& e) {
    throw usage_error_at(option, whole, e.message());
  }
}

CLI::Validator quantity(const model::QuantityRule& rule, std::string option) {
  const std::string description = fmt::format("{} (or with its unit{})", rule.unit,
                                              rule.dimension == model::kAngle ? ": 0.01deg, 5urad" : ": 1um, 0.0001in");
  return CLI::Validator(
      [rule, option](std::string& text) -> std::string {
        const double value = quantity_in(text, rule, option, text);
        text = fmt::format("{:.17g}", value);
        return {};
      },
      description);
}

std::optional<Error> mistyped(const CLI::App& app, int argc, const char* const* argv) {
  const std::vector<std::string> commands = subcommand_names(app);
  const CLI::App* command = &app;
  bool command_named = false;
  std::string first_word;
  for (int i = 1; i < argc; ++i) {
    const std::string_view w = argv[i];
    if (w == "--") break;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      if (!sub->get_name().empty() && w == sub->get_name()) command = sub, command_named = true;
    if (command_named) break;
    if (first_word.empty() && !w.starts_with("-")) first_word = std::string(w);
  }
  // `ccomp chek data.csv --report r.html`: check's option is the main job's unknown, but the
  // mistake is the command.
  if (!command_named && !first_word.empty() && !std::filesystem::exists(first_word))
    if (const std::string near = util::nearest_name(first_word, views(commands)); !near.empty())
      return Error(ErrorKind::usage, fmt::format("unknown command '{}'; did you mean '{}'?", first_word, near));
  const std::vector<std::string> known = long_options(*command);
  for (int i = 1; i < argc; ++i) {
    const std::string_view w = argv[i];
    if (w == "--") break;
    if (!w.starts_with("--") || w.size() == 2) continue;
    const std::string_view name = w.substr(0, w.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    const std::string near = util::nearest_name(name, views(known));
    const std::string of = command == &app ? "" : fmt::format(" of '{}'", command->get_name());
    return error_at_word(static_cast<std::size_t>(i), 0,
                         near.empty() ? fmt::format("unknown option '{}'{} (see --help)", name, of)
                                      : fmt::format("unknown option '{}'{}; did you mean '{}'?", name, of, near));
  }
  return std::nullopt;
}

void refuse_mistyped_command(const CLI::App& app, const std::vector<std::string>& inputs) {
  if (inputs.empty()) return;
  const std::string& first = inputs.front();
  if (first == "-" || std::filesystem::exists(first)) return;
  if (first.find_first_of("./\\") != std::string::npos) return;  // a path: the job says it is missing
  const std::vector<std::string> commands = subcommand_names(app);
  const std::string near = util::nearest_name(first, views(commands));
  throw Error(ErrorKind::usage,
              near.empty() ? fmt::format("'{}' is neither a program file nor a command ({}; or the main job: ccomp "
                                         "in.nc -m machine.yaml -o out.nc)",
                                         first, listed(commands))
                           : fmt::format("unknown command '{}'; did you mean '{}'?", first, near));
}

}  // namespace ccomp::cli
