#pragma once
// Each podid subcommand lives in apps/cmd_<name>.cpp and registers itself on
// the root CLI::App with one Add...Command function, called from main.cpp.
// A command's callback throws std::invalid_argument for bad input; main()
// prints it on one line and exits 1.

#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>

namespace podid::cli {

/// A command that ran but did not succeed (e.g. a simulation that diverged):
/// main() prints the message and exits with `exit_code` (2 by convention).
class CommandFailed : public std::runtime_error {
 public:
  CommandFailed(const std::string& message, int exit_code = 2)
      : std::runtime_error(message), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

void AddModesCommand(CLI::App& app);
void AddSimulateCommand(CLI::App& app);
void AddPodCommand(CLI::App& app);
void AddCwtCommand(CLI::App& app);
void AddPlanCommand(CLI::App& app);
void AddIdentifyCommand(CLI::App& app);
void AddLandscapeCommand(CLI::App& app);

}  // namespace podid::cli
