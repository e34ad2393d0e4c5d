#pragma once
// The command table of amb-host: every sub-command (nested ones as "hybrid train") with its
// summary, one example and its options as the checks recorded them (cli_checks.hpp). The
// --help footers, the man page (packaging/man/amb-host.1 is `amb-host --man`) and the
// bad-input sweep (tests/cli, which reads `amb-host --command-table`) are all made from it.
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace amb::host {

/// One runnable example of `path` ("fit", "hybrid train"); "" when there is none (a test
/// requires one for every sub-command).
std::string command_example(const std::string& path);

/// Adds "Example:" and the exit status to the footer of every sub-command of `app`.
void add_examples_to_help(CLI::App& app);

/// The table as JSON: {"program", "version", "commands": [{"path", "summary", "example",
/// "options": [{"name", "positional", "flag", "type", "required", "default", "range",
/// "file_kind", "output", "description"}]}]}.
nlohmann::json command_table(const CLI::App& app, const std::string& version);

/// The man page (roff) generated from the table, with EXIT STATUS and EXAMPLES.
std::string man_page(const CLI::App& app, const std::string& version);

}  // namespace amb::host
