#include "cli_common.hpp"

#include <filesystem>

namespace podid::cli {

void CaseArguments::AddTo(CLI::App& command) {
  command.add_option("case", path, "Case file (TOML, see docs/case-file.md)")->required();
  command.add_option("--set", sets,
                     "Override a case-file key, e.g. --set nonlinearity.0.k3=2.5e9 (repeatable)")
      ->type_name("KEY=VALUE");
}

CaseDocument CaseArguments::Load() const {
  CaseDocument document = CaseDocument::Load(path);
  ApplySetArguments(document, sets);
  return document;
}

std::string DefaultOutput(const std::string& input, const std::string& suffix) {
  return std::filesystem::path(input).stem().string() + suffix;
}

}  // namespace podid::cli
