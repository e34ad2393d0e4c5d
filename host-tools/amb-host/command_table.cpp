#include "host-tools/amb-host/command_table.hpp"

#include <map>
#include <vector>

#include "host-tools/amb-host/cli_checks.hpp"

namespace amb::host {

namespace {

// One example per sub-command; file names are what the tools write or what
// ../shared/data/measured holds (the sweep in tests/cli substitutes files of the same kind).
const std::map<std::string, std::string>& examples() {
  static const std::map<std::string, std::string> e = {
      {"bearing-check", "amb-host bearing-check --mat 1797_IR_7_DE12.mat --var DE_time --fs 12000 --rpm 1797 --bearing 6205"},
      {"envelope", "amb-host envelope studies/envelope-small.toml --out amb-out/envelope-small"},
      {"export", "amb-host export amb-out/event_00000001.ambe --out amb-out/event_00000001"},
      {"fetch", "amb-host fetch --host 192.168.1.20 --out events --wear events/wear_record.ambw"},
      {"fit", "amb-host fit amb-out/event_00000001.json --wear-out amb-out/wear_record.ambw --json"},
      {"fleet", "amb-host fleet --store amb-out/fleet.sqlite list"},
      {"fleet add", "amb-host fleet --store amb-out/fleet.sqlite --create add amb-out"},
      {"fleet list", "amb-host fleet --store amb-out/fleet.sqlite list --json"},
      {"fleet trend", "amb-host fleet --store amb-out/fleet.sqlite trend --machine bath-amb-rig"},
      {"fleet report", "amb-host fleet --store amb-out/fleet.sqlite report --out amb-out/fleet.html"},
      {"hybrid", "amb-host hybrid predict --model m.json --state inner_race --rpm 1750 --load 2"},
      {"hybrid train", "amb-host hybrid train --out m.json --record 1797_IR_7_DE12.mat,state=inner_race,rpm=1797,load=0"},
      {"hybrid predict", "amb-host hybrid predict --model m.json --state inner_race --rpm 1750 --load 2 --json"},
      {"import", "amb-host import amb-out/event_00000001.ambe"},
      {"journal-sil", "amb-host journal-sil --out ev/w1 --wear 3p:46.5,23,77 --eccentricity 0.7 --record 5"},
      {"replay", "amb-host replay amb-out/event_00000001.ambe --json"},
      {"report", "amb-host report amb-out/event_00000001.ambe --wear amb-out/wear_record.ambw --out report.html"},
      {"residual", "amb-host residual amb-out/steady_undeclared.json --json"},
      {"scenario", "amb-host scenario --board bath-amb-rig --json"},
      {"sweep", "amb-host sweep --board bath-amb-rig --out amb-out --json"},
      {"track-speed", "amb-host track-speed --mat data-20130311T030024Z.mat --var vibration --fs 97656 --profile profiles/windturbine-hss.toml"},
      {"wear-id", "amb-host wear-id ev/w1.json --model 3p --window 2 --json"},
      {"writeback", "amb-host writeback amb-out/wear_record.ambw --host 192.168.1.20 --board bath-amb-rig"},
  };
  return e;
}

void collect(const CLI::App& app, const std::string& prefix, std::vector<std::pair<std::string, const CLI::App*>>& out) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string path = prefix.empty() ? sub->get_name() : prefix + " " + sub->get_name();
    out.emplace_back(path, sub);
    collect(*sub, path, out);
  }
}

std::string base_type(const CLI::Option* o) {
  const std::string t = o->get_type_name();
  return t.substr(0, t.find(':'));
}

nlohmann::json option_json(const CLI::Option* o) {
  nlohmann::json j;
  j["name"] = o->get_name();
  j["positional"] = o->get_positional();
  j["flag"] = o->get_expected_min() == 0;
  j["type"] = base_type(o);
  j["required"] = o->get_required();
  j["default"] = o->get_default_str();
  j["description"] = o->get_description();
  j["range"] = nullptr;
  j["file_kind"] = nullptr;
  j["output"] = false;
  j["output_file"] = false;
  if (const cli::OptionInfo* i = cli::info(o)) {
    if (i->range)
      j["range"] = {{"lo", i->range->lo}, {"hi", i->range->hi}, {"lo_open", i->range->lo_open},
                    {"integer", i->range->integer}, {"unit", i->range->unit}};
    if (!i->file_kind.empty()) j["file_kind"] = i->file_kind;
    j["output"] = i->output;
    j["output_file"] = i->output_file;
  }
  return j;
}

/// roff: escape backslashes and leading dots/quotes; '-' as \- (a real minus in options).
std::string roff(const std::string& s) {
  std::string r;
  for (char c : s) {
    if (c == '\\') r += "\\e";
    else if (c == '-') r += "\\-";
    else r += c;
  }
  if (!r.empty() && (r[0] == '.' || r[0] == '\'')) r = "\\&" + r;
  return r;
}

std::vector<const CLI::Option*> options_of(const CLI::App* app) {
  std::vector<const CLI::Option*> out;
  for (const CLI::Option* o : app->get_options([](const CLI::Option* x) { return x->get_name() != "--help"; }))
    out.push_back(o);
  return out;
}

}  // namespace

std::string command_example(const std::string& path) {
  const auto it = examples().find(path);
  return it == examples().end() ? std::string() : it->second;
}

void add_examples_to_help(CLI::App& app) {
  std::vector<std::pair<std::string, const CLI::App*>> all;
  collect(app, "", all);
  std::map<const CLI::App*, std::string> original;
  original[&app] = app.get_footer();
  for (auto& [path, sub] : all) original[sub] = sub->get_footer();
  for (auto& [path, sub] : all) {
    CLI::App* s = const_cast<CLI::App*>(sub);
    // A sub-command starts with its parent's footer (CLI11): keep only a footer of its own.
    const std::string own = original[sub] == original[sub->get_parent()] ? std::string() : original[sub];
    std::string foot;
    const std::string ex = command_example(path);
    if (!ex.empty()) foot += "Example:\n  " + ex + "\n";
    if (own.find("Exit status") == std::string::npos)
      foot += "Exit status: 0 success, 1 bad input (the option or file is named), 2 the work itself failed.";
    if (!own.empty()) foot += (foot.empty() || foot.back() == '\n' ? "" : "\n") + own;
    s->footer(foot);
  }
}

nlohmann::json command_table(const CLI::App& app, const std::string& version) {
  std::vector<std::pair<std::string, const CLI::App*>> all;
  collect(app, "", all);
  nlohmann::json cmds = nlohmann::json::array();
  for (const auto& [path, sub] : all) {
    nlohmann::json c;
    c["path"] = path;
    c["summary"] = sub->get_description();
    c["example"] = command_example(path);
    c["has_subcommands"] = !sub->get_subcommands([](const CLI::App*) { return true; }).empty();
    nlohmann::json opts = nlohmann::json::array();
    for (const CLI::Option* o : options_of(sub)) opts.push_back(option_json(o));
    c["options"] = opts;
    cmds.push_back(c);
  }
  return {{"program", "amb-host"}, {"version", version}, {"commands", cmds}};
}

std::string man_page(const CLI::App& app, const std::string& version) {
  std::vector<std::pair<std::string, const CLI::App*>> all;
  collect(app, "", all);
  std::string m;
  m += ".\\\" Generated by 'amb-host --man' from the command table (host-tools/amb-host); do not edit.\n";
  m += ".TH AMB-HOST 1 \"\" \"amb-supervisor " + version + "\" \"User Commands\"\n";
  m += ".SH NAME\namb-host \\- host tools of the AMB supervisor: drop events, fits, wear records\n";
  m += ".SH SYNOPSIS\n.B amb-host\n.I SUB-COMMAND\n.RI [ OPTIONS ]\n.br\n.B amb-host\n.I SUB-COMMAND\n.B \\-\\-help\n"
       ".br\n.B amb-host\n.B \\-\\-version\n";
  m += ".SH DESCRIPTION\n.B amb-host\nturns the rotor-drop events captured by an\n.BR amb-firmware (8)\n"
       "board into a wear record of the auxiliary (touchdown) bearings: it downloads events from the\n"
       "board, fits the multibody drop model, traces residuals to missing effects, writes reports and\n"
       "writes the wear record back to the board. Sub-commands that compute figures print them as JSON\n"
       "with\n.BR \\-\\-json\n(stdout carries the JSON only; progress and messages go to stderr).\n"
       "Every number is checked to be finite and inside the range given below; every input file is\n"
       "checked to exist, to be non-empty and to be of the expected kind before any work starts.\n";
  m += ".SH SUB-COMMANDS\n";
  for (const auto& [path, sub] : all) {
    m += ".SS " + roff(path) + "\n" + roff(sub->get_description()) + "\n";
    for (const CLI::Option* o : options_of(sub)) {
      std::string head = o->get_positional() ? "\\fI" + roff(o->get_name()) + "\\fR" : "\\fB" + roff(o->get_name()) + "\\fR";
      if (!o->get_positional() && o->get_expected_min() > 0) head += " \\fI" + roff(base_type(o)) + "\\fR";
      m += ".TP\n" + head + "\n" + roff(o->get_description());
      std::string extra;
      if (o->get_required()) extra += "required";
      const cli::OptionInfo* i = cli::info(o);
      if (i && i->range) extra += std::string(extra.empty() ? "" : "; ") + "allowed " + amb::cli::describe(*i->range);
      if (i && !i->file_kind.empty()) extra += std::string(extra.empty() ? "" : "; ") + "input file: " + i->file_kind;
      if (!o->get_required() && !o->get_default_str().empty() && o->get_expected_min() > 0)
        extra += std::string(extra.empty() ? "" : "; ") + "default " + o->get_default_str();
      if (!extra.empty()) m += " (" + roff(extra) + ")";
      m += "\n";
    }
    const std::string ex = command_example(path);
    if (!ex.empty()) m += ".PP\nExample:\n.PP\n.nf\n.RS 4\n" + roff(ex) + "\n.RE\n.fi\n";
  }
  m += ".SH OPTIONS\n.TP\n.BR \\-h \", \" \\-\\-help\nPrint the sub-commands, or the options of one sub-command.\n"
       ".TP\n.B \\-\\-version\nPrint the version.\n";
  m += ".SH EXIT STATUS\n.TP\n.B 0\nSuccess.\n.TP\n.B 1\nBad input: an option out of range or not a number, a missing,"
       " empty, truncated or wrong kind of file, an unknown board. The message names the option or the file; nothing"
       " is written.\n.TP\n.B 2\nThe work itself failed (a fit that did not run, a replay that did not reproduce the"
       " event, a board that did not answer).\n";
  m += ".SH ENVIRONMENT\n.TP\n.B AMB_FLEET_STORE\nDefault store of\n.BR \"amb-host fleet\" .\n"
       ".TP\n.B AMB_ARM_KEY\nArm key of\n.B amb-host writeback\nwhen neither\n.B \\-\\-arm\\-key\nnor\n.B \\-\\-board\nis given.\n";
  m += ".SH EXAMPLES\n";
  for (const auto& [path, sub] : all) {
    (void)sub;
    const std::string ex = command_example(path);
    if (ex.empty() || path.find(' ') != std::string::npos) continue;
    m += ".PP\n.nf\n.RS 4\n" + roff(ex) + "\n.RE\n.fi\n";
  }
  m += ".SH SEE ALSO\n.BR amb-plant (1),\n.BR amb-firmware (8)\n";
  return m;
}

}  // namespace amb::host
