// libFuzzer target: case files. The input is TOML text, optionally followed by
// a line "---" and `key=value` lines applied with CaseDocument::Set (as
// `--set`); then the whole validation, ToSpec(). Invalid input must end in
// std::invalid_argument; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "podid/core/case_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t separator = input.find("\n---\n");
  const std::string_view toml = input.substr(0, separator);
  std::string_view sets =
      separator == std::string_view::npos ? std::string_view{} : input.substr(separator + 5);
  try {
    // Relative force files resolve into a folder that does not exist.
    podid::CaseDocument document =
        podid::CaseDocument::Parse(toml, "fuzz.toml", "/nonexistent-podid-fuzz");
    while (!sets.empty()) {
      const std::size_t end = sets.find('\n');
      const std::string line(sets.substr(0, end));
      sets = end == std::string_view::npos ? std::string_view{} : sets.substr(end + 1);
      try {
        podid::ApplySetArguments(document, {line});
      } catch (const std::invalid_argument&) {
        // A rejected --set leaves the document usable: go on with the others.
      }
    }
    const podid::CaseSpec spec = document.ToSpec();
    (void)spec;
    // Every identification parameter's key can be read and written back.
    podid::CaseDocument copy = document;
    for (const auto& parameter : spec.parameters) {
      if (copy.Has(parameter.key)) copy.SetNumber(parameter.key, copy.GetNumber(parameter.key));
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
