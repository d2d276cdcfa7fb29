#include "cli_manual.h"

#include <fmt/format.h>

namespace pluvia::cli {
namespace {

std::vector<const CLI::App*> subcommandsOf(const CLI::App& command) {
  return command.get_subcommands([](const CLI::App*) { return true; });
}

// The command's words after "pluvia": "farm slurm".
std::string commandPath(const CLI::App& command) {
  std::string path;
  for (const CLI::App* at = &command; at->get_parent(); at = at->get_parent())
    path = at->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

// Text made safe for roff: backslashes escaped, hyphens as minus signs (so that options copy
// and paste), and a line never starting with a control character.
std::string roff(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}

// "-p, --preset TEXT" for an option, "INPUT" for a positional.
std::string optionHeading(const CLI::Option& option) {
  if (option.get_positional()) return option.get_name(true, false);
  std::string names = option.get_name(false, true);
  for (size_t at = names.find(','); at != std::string::npos; at = names.find(',', at + 2))
    names.replace(at, 1, ", ");
  if (option.get_expected_min() > 0 && !option.get_type_name().empty())
    names += " " + option.get_type_name();
  return names;
}

// The program's description without its leading "pluvia: ", which NAME already says.
std::string descriptionAfterName(const CLI::App& root) {
  const std::string prefix = root.get_name() + ": ";
  const std::string& text = root.get_description();
  return text.rfind(prefix, 0) == 0 ? text.substr(prefix.size()) : text;
}

void appendCommand(std::string& page, const CLI::App& command) {
  page += fmt::format(".SS \"pluvia {}\"\n{}\n", roff(commandPath(command)),
                      roff(command.get_description()));
  for (const CLI::Option* option : command.get_options()) {
    if (option->get_name() == "--help") continue;
    page += fmt::format(".TP\n.B {}\n{}\n", roff(optionHeading(*option)),
                        roff(option->get_description()));
  }
  for (const CLI::App* sub : subcommandsOf(command)) appendCommand(page, *sub);
}

// Every long and short name of `command`'s options, and its subcommands' names.
std::string wordsOf(const CLI::App& command) {
  std::vector<std::string> words;
  for (const CLI::App* sub : subcommandsOf(command)) words.push_back(sub->get_name());
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_snames()) words.push_back("-" + name);
    for (const std::string& name : option->get_lnames()) words.push_back("--" + name);
  }
  return fmt::format("{}", fmt::join(words, " "));
}

void appendCompletionCases(std::string& script, const CLI::App& command) {
  script += fmt::format("    \"{}\") words=\"{}\" ;;\n", commandPath(command), wordsOf(command));
  for (const CLI::App* sub : subcommandsOf(command)) appendCompletionCases(script, *sub);
}

}  // namespace

std::string manPage(const CLI::App& root, const std::string& version, const std::string& exitCodes,
                    const std::string& environment) {
  std::string page = fmt::format(
      ".TH PLUVIA 1 \"\" \"pluvia {}\" \"User Commands\"\n"
      ".SH NAME\npluvia \\- {}\n"
      ".SH SYNOPSIS\n.B pluvia\n[\\fB\\-q\\fR | \\fB\\-v\\fR] [\\fB\\-\\-log\\fR \\fIFILE\\fR] "
      "\\fICOMMAND\\fR [\\fIOPTIONS\\fR]\n"
      ".SH DESCRIPTION\n"
      "A JSON preset (\\fBpluvia presets\\fR lists the shipped ones) turns a clip into rained "
      "frames. \\fB\\-q\\fR, \\fB\\-v\\fR and \\fB\\-\\-log\\fR belong to the program and may "
      "stand anywhere on the line.\n",
      roff(version), roff(descriptionAfterName(root)));
  page += ".SH OPTIONS\n";
  for (const CLI::Option* option : root.get_options())
    page += fmt::format(".TP\n.B {}\n{}\n", roff(optionHeading(*option)),
                        roff(option->get_description()));
  page += ".SH COMMANDS\n";
  for (const CLI::App* command : subcommandsOf(root)) appendCommand(page, *command);
  page +=
      fmt::format(".SH EXIT STATUS\n{}\n.SH ENVIRONMENT\n{}\n", roff(exitCodes), roff(environment));
  return page;
}

std::string bashCompletion(const CLI::App& root, const std::vector<std::string>& presetNames) {
  std::string script =
      "# bash completion for pluvia, made by `pluvia completion` from its command line.\n"
      "# Load it with: source <(pluvia completion)\n"
      "_pluvia() {\n"
      "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" prev=\"${COMP_WORDS[COMP_CWORD-1]}\"\n"
      "  local path=\"\" words i\n"
      "  _pluvia_words() {\n"
      "    case \"$1\" in\n";
  appendCompletionCases(script, root);
  script += fmt::format(
      "    *) words=\"\" ;;\n"
      "    esac\n"
      "  }}\n"
      "  # The command the words so far name: each word that is a subcommand of the path.\n"
      "  for ((i = 1; i < COMP_CWORD; i++)); do\n"
      "    _pluvia_words \"$path\"\n"
      "    local next=\"${{path:+$path }}${{COMP_WORDS[i]}}\"\n"
      "    case \" $words \" in *\" ${{COMP_WORDS[i]}} \"*) [[ ${{COMP_WORDS[i]}} != -* ]] && "
      "path=\"$next\" ;; esac\n"
      "  done\n"
      "  case \"$prev\" in\n"
      "    -p|--preset|--presets) COMPREPLY=($(compgen -W \"{}\" -f -- \"$cur\")); return ;;\n"
      "  esac\n"
      "  _pluvia_words \"$path\"\n"
      "  if [[ $cur == -* ]]; then\n"
      "    COMPREPLY=($(compgen -W \"$words -q -v --log\" -- \"$cur\"))\n"
      "  else\n"
      "    local subs=\"\" w\n"
      "    for w in $words; do [[ $w == -* ]] || subs+=\"$w \"; done\n"
      "    # A command with subcommands needs one of them; the others take files.\n"
      "    if [[ -n $subs ]]; then COMPREPLY=($(compgen -W \"$subs\" -- \"$cur\"))\n"
      "    else COMPREPLY=($(compgen -f -- \"$cur\")); fi\n"
      "  fi\n"
      "}}\n"
      "complete -o filenames -F _pluvia pluvia\n",
      fmt::join(presetNames, " "));
  return script;
}

}  // namespace pluvia::cli
