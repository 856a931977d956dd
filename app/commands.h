#pragma once
// Sub-commands of the `lacet` command-line tool; each registers itself on the CLI11 app.

#include <CLI/CLI.hpp>

namespace lacet::app {

void addSynthCommand(CLI::App& app);
void addCheckCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addImportCommand(CLI::App& app);
void addEditCommand(CLI::App& app);

}  // namespace lacet::app
