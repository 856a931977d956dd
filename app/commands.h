#pragma once
// Sub-commands of the `lacet` command-line tool; each registers itself on the CLI11 app.

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "pyramid/pyramid_build.h"

namespace lacet::app {

void addSynthCommand(CLI::App& app);
void addCheckCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addImportCommand(CLI::App& app);
void addEditCommand(CLI::App& app);
void addPyramidCommand(CLI::App& app);

// `lacet pyramid info` and `lacet info` of a pyramid file: the JSON report; exits 2 when a tile is
// corrupt or missing.
void printPyramidInfo(const std::string& path);
// A pyramid run's figures (`what`: "built", "updated"), as text or JSON.
nlohmann::json pyramidStatsJson(const PyramidStats& s, const std::string& path);
void printPyramidStats(const PyramidStats& s, const std::string& what, const std::string& path, bool json);
// `lacet pyramid build --shards`: the build over the ranks of an MPI job (app/pyramid_mpi.cpp when
// built with LACET_MPI; otherwise it refuses, saying so).
// `region`: each rank's shards read only their part of the scene file (PyramidJob over the file).
void runShardedPyramidBuild(const std::string& scene, const std::string& out, const PyramidParams& params, bool force, bool json,
                            bool region);

}  // namespace lacet::app
