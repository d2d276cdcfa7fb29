#pragma once
// The command line's own documentation, made from its CLI11 definition so that it cannot drift
// from what the parser accepts: a man page (roff, `pluvia man | man -l -`) and a bash completion
// script (`source <(pluvia completion)`).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace pluvia::cli {

// The whole program's man page, section 1: every command and subcommand with its options.
// `exitCodes` and `environment` are the EXIT STATUS and ENVIRONMENT sections' text.
std::string manPage(const CLI::App& root, const std::string& version, const std::string& exitCodes,
                    const std::string& environment);

// A bash completion function for `root`'s commands, their options and, after -p/--preset or
// --presets, the shipped preset names `presetNames`; files elsewhere.
std::string bashCompletion(const CLI::App& root, const std::vector<std::string>& presetNames);

}  // namespace pluvia::cli
