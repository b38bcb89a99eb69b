// podid: identification of nonlinear structures by POD and wavelets.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>

#include "commands.hpp"
#include "mpi_session.hpp"
#include "podid/core/error.hpp"
#include "podid/core/temp_files.hpp"

namespace {

/// One line for the terminal: line breaks become "; ", other control
/// characters \xNN, so no message can move the cursor or fake a prompt.
std::string OneLine(const std::string& text) {
  std::string out;
  std::size_t end = text.size();
  while (end > 0 && (text[end - 1] == '\n' || text[end - 1] == '\r')) --end;
  for (std::size_t i = 0; i < end; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      out += "; ";
    } else if (c < 0x20 || c == 0x7f) {
      static const char* const kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

void PrintError(const std::string& message) {
  namespace mpi = podid::cli::mpi;
  if (mpi::Active()) {
    std::fprintf(stderr, "podid: error (rank %d of %d): %s\n", mpi::Rank(), mpi::Size(),
                 OneLine(message).c_str());
    return;
  }
  std::fprintf(stderr, "podid: error: %s\n", OneLine(message).c_str());
}

/// The type an option reads, for "expected ...": CLI11's type names.
std::string ExpectedValue(const CLI::App* command, const std::string& name) {
  const CLI::Option* option = command == nullptr ? nullptr : command->get_option_no_throw(name);
  const std::string type = option == nullptr ? std::string() : option->get_type_name();
  if (type == "UINT") return "a whole number >= 0";
  if (type == "INT") return "a whole number";
  if (type == "FLOAT") return "a number";
  return type.empty() ? "a value of the option's type" : "a value of type " + type;
}

/// CLI11's (2.1) wording of three mistakes, told in podid's own form
/// "WHERE: expected X, got Y" (core/error.hpp's ThrowInvalid). They are
/// recognised by the error's type and CLI11's fixed text; any other message
/// passes unchanged.
std::string ArgumentMessage(const CLI::ParseError& e, const CLI::App* command) {
  const std::string text = e.what();
  // "Could not convert: --samples = 1e9"
  static constexpr std::string_view kConvert = "Could not convert: ";
  if (dynamic_cast<const CLI::ConversionError*>(&e) != nullptr && text.rfind(kConvert, 0) == 0) {
    const std::size_t equals = text.find(" = ", kConvert.size());
    if (equals != std::string::npos) {
      const std::string name = text.substr(kConvert.size(), equals - kConvert.size());
      return name + ": expected " + ExpectedValue(command, name) + ", got " +
             podid::Excerpt(text.substr(equals + 3));
    }
  }
  // "--fmin: At Most 1 required but received 2": an option given twice.
  static constexpr std::string_view kAtMost = ": At Most ";
  if (const std::size_t at = text.find(kAtMost);
      dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && at != std::string::npos) {
    unsigned long most = 0;
    unsigned long received = 0;
    if (std::sscanf(text.c_str() + at + kAtMost.size(), "%lu required but received %lu", &most,
                    &received) == 2) {
      return text.substr(0, at) + ": expected " +
             (most == 1 ? std::string("one value (the option given once)")
                        : "at most " + std::to_string(most) + " values") +
             ", got " + std::to_string(received);
    }
  }
  // "--detrend: foo not in {none,constant,linear}" (CLI::IsMember).
  static constexpr std::string_view kNotIn = " not in {";
  const std::size_t colon = text.find(": ");
  const std::size_t not_in = text.rfind(kNotIn);
  if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr && colon != std::string::npos &&
      not_in != std::string::npos && not_in > colon && text.back() == '}') {
    const std::size_t list = not_in + kNotIn.size();
    return text.substr(0, colon) + ": expected one of " +
           podid::ReplaceAll(text.substr(list, text.size() - 1 - list), ",", ", ") + ", got " +
           podid::Excerpt(text.substr(colon + 2, not_in - colon - 2));
  }
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  // Under mpirun/srun (and built with MPI): MPI for the whole run; else nothing.
  podid::cli::mpi::Session mpi_session(&argc, &argv);
  CLI::App app{
      "podid: identify the parameters of nonlinear mechanical structures from measured\n"
      "time histories, with proper orthogonal decomposition (POD) and the Morlet wavelet\n"
      "transform (Lenaerts, Kerschen & Golinval). Units are SI throughout.",
      "podid"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "podid 0.1.0");
  app.footer(
      "Run 'podid COMMAND --help' for a command's options. Docs: docs/cli.md\n"
      "Exit status: 0 success, 1 invalid input or arguments (one line on stderr),\n"
      "2 a computation that ran but failed, 130 interrupted.");

  podid::cli::AddModesCommand(app);
  podid::cli::AddSimulateCommand(app);
  podid::cli::AddPodCommand(app);
  podid::cli::AddCwtCommand(app);
  podid::cli::AddPlanCommand(app);
  podid::cli::AddIdentifyCommand(app);
  podid::cli::AddLandscapeCommand(app);

  // Under several MPI ranks only the commands that spread their work run; the
  // others would compute the same thing on every rank and race on the outputs.
  if (podid::cli::mpi::Active()) {
    for (int i = 1; i < argc; ++i) {
      const std::string word = argv[i];
      if (word.empty() || word[0] == '-') continue;
      if (word != "landscape" && word != "identify") {
        PrintError("podid " + word + " runs as one process: start it without mpirun (only " +
                   "'podid landscape' and 'podid identify --multistart' spread over MPI ranks)");
        return 1;
      }
      break;
    }
  }

  // SIGINT, SIGTERM, SIGHUP, ... remove the temporary files of a write in progress.
  podid::InstallTemporaryFileCleanup();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0: print them as CLI11 does.
    if (e.get_exit_code() == 0) return app.exit(e);
    // Any other argument error: one line, the documented exit status 1.
    std::string help = "podid --help";
    const auto parsed = app.get_subcommands();
    if (!parsed.empty()) help = "podid " + parsed.front()->get_name() + " --help";
    PrintError(ArgumentMessage(e, parsed.empty() ? nullptr : parsed.front()) + " (see '" + help +
               "')");
    return 1;
  } catch (const podid::cli::CommandFailed& e) {
    std::fprintf(stderr, "podid: %s\n", OneLine(e.what()).c_str());
    return e.exit_code();
  } catch (const std::bad_alloc&) {
    // Never a bare "std::bad_alloc": the documented limits bound what an input
    // may ask for; within them, the machine ran out of memory.
    PrintError(
        "out of memory: the data, case or options ask for more memory than this machine "
        "has (limits: docs/case-file.md, docs/cli.md); use a shorter record, a coarser time "
        "step or fewer points");
    return 1;
  } catch (const std::exception& e) {
    PrintError(e.what());
    return 1;
  }
  // A full disk behind stdout loses the printed results: not a success
  // (`podid modes CASE > /dev/full` exited 0). A closed pipe ends the process
  // by SIGPIPE before this, as for any tool.
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
    PrintError(std::string("standard output: expected the results written, got a write error") +
               (errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : std::string()));
    return 1;
  }
  return 0;
}
