// podid: identification of nonlinear structures by POD and wavelets.
#include <cstdio>
#include <exception>
#include <stdexcept>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "podid: identify the parameters of nonlinear mechanical structures from measured\n"
      "time histories, with proper orthogonal decomposition (POD) and the Morlet wavelet\n"
      "transform (Lenaerts, Kerschen & Golinval). Units are SI throughout.",
      "podid"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "podid 0.1.0");
  app.footer("Run 'podid COMMAND --help' for a command's options. Docs: docs/cli.md");

  podid::cli::AddModesCommand(app);
  podid::cli::AddSimulateCommand(app);
  podid::cli::AddPodCommand(app);
  podid::cli::AddCwtCommand(app);
  podid::cli::AddIdentifyCommand(app);
  podid::cli::AddLandscapeCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const podid::cli::CommandFailed& e) {
    std::fprintf(stderr, "podid: %s\n", e.what());
    return e.exit_code();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "podid: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "podid: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
