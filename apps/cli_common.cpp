#include "cli_common.hpp"

#include <sys/stat.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid::cli {

void CaseArguments::AddTo(CLI::App& command) {
  command.add_option("case", path, "Case file (TOML, see docs/case-file.md)")->required();
  command
      .add_option("--set", sets,
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

std::vector<NamedFile> CaseInputFiles(const CaseArguments& arguments) {
  std::vector<NamedFile> files = {{"case file", arguments.path}};
  const CaseSpec spec = arguments.Load().ToSpec();
  // Relative to the case file's folder, as CaseDocument resolves them.
  auto add = [&](const std::string& what, const std::string& name) {
    std::filesystem::path path(name);
    if (path.is_relative()) path = std::filesystem::path(arguments.path).parent_path() / path;
    files.push_back({what, path.string()});
  };
  auto add_history = [&](const std::string& what, const ExcitationHistory& history) {
    if (history.type == ForceType::kFile && !history.file.empty()) add(what, history.file);
  };
  add_history("force file", spec.force.history_N);
  for (const ForceSpec& force : spec.forces) add_history("force file", force.history_N);
  add_history("base acceleration file", spec.base.history_m_per_s2);
  if (!spec.base.influence_file.empty()) add("base influence file", spec.base.influence_file);
  // [data] file or -m: already resolved against the case's folder.
  if (!spec.data.file.empty()) files.push_back({"data file", spec.data.file});
  if (spec.model.type == ModelType::kMatrices) {
    if (!spec.model.file.empty()) {
      add("model file", spec.model.file);
    } else {  // Matrix Market files, one per matrix
      add("mass matrix file", spec.model.mass);
      add("stiffness matrix file", spec.model.stiffness);
      if (!spec.model.damping.empty()) add("damping matrix file", spec.model.damping);
    }
  }
  return files;
}

namespace {

/// Device and inode of an existing regular file (symlinks followed).
bool RegularFileId(const std::string& path, std::uint64_t* device, std::uint64_t* inode) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0 || !S_ISREG(status.st_mode)) return false;
  *device = status.st_dev;
  *inode = status.st_ino;
  return true;
}

std::string Describe(const NamedFile& file) { return file.what + " " + file.path; }

}  // namespace

void CheckOutputs(const std::vector<NamedFile>& inputs, const std::vector<NamedFile>& outputs) {
  std::vector<std::pair<const NamedFile*, OutputTarget>> checked;
  for (const NamedFile& output : outputs) {
    if (output.path.empty()) continue;
    OutputTarget target;
    try {
      target = ResolveOutput(output.path);
    } catch (const std::exception& e) {
      throw std::invalid_argument(output.what + ": " + e.what());
    }
    for (const NamedFile& input : inputs) {
      std::uint64_t device = 0, inode = 0;
      if (target.exists && RegularFileId(input.path, &device, &inode) && device == target.device &&
          inode == target.inode) {
        ThrowInvalid(
            output.what,
            "a file other than the " + Describe(input) + " (writing it would destroy that input)",
            "\"" + output.path + "\", the same file");
      }
    }
    for (const auto& [other, other_target] : checked) {
      const bool same =
          target.exists && other_target.exists
              ? target.device == other_target.device && target.inode == other_target.inode
              : target.path == other_target.path;
      if (same && target.kind == OutputTarget::Kind::kFile) {
        ThrowInvalid(output.what, "a file other than " + Describe(*other),
                     "\"" + output.path + "\", the same file");
      }
    }
    checked.emplace_back(&output, target);
  }
}

void CheckOutputFolder(const NamedFile& folder) {
  namespace fs = std::filesystem;
  if (folder.path.empty()) return;
  fs::path existing(folder.path);
  std::error_code error;
  // The nearest existing ancestor: create_directories makes the rest.
  while (!fs::exists(existing, error) && existing.has_relative_path() &&
         existing != existing.parent_path()) {
    existing = existing.has_parent_path() ? existing.parent_path() : fs::path(".");
  }
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, error)) {
    ThrowInvalid(folder.what, "a folder (or a path to create one)",
                 "\"" + folder.path + "\": " + existing.string() + " is not a folder");
  }
  // As ResolveOutput judges a file's folder (a 0555 one is read-only for root too).
  const std::string why = FolderNotWritable(existing.string());
  if (!why.empty()) {
    ThrowInvalid(folder.what, "a writable folder",
                 "\"" + folder.path + "\": " + existing.string() + ": " + why);
  }
}

CLI::Validator NonEmptyPath(const std::string& what) { return NonEmpty(what); }

CLI::Validator NonEmpty(const std::string& what) {
  return CLI::Validator(
      [what](std::string& text) -> std::string {
        return text.empty() ? "expected " + what + ", got an empty one" : std::string();
      },
      "");
}

CLI::Validator IntegerIn(long long lower, long long upper) {
  const std::string range = "[" + std::to_string(lower) + ", " + std::to_string(upper) + "]";
  return CLI::Validator(
      [lower, upper, range](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (error != std::errc() || stop != end || value < lower || value > upper) {
          const std::string shown = text.size() > 40 ? text.substr(0, 40) + "..." : text;
          return "expected an integer in " + range + ", got \"" + shown + "\"";
        }
        return {};
      },
      "INT in " + range);
}

CLI::Validator NumberIn(NumberEnd lower, NumberEnd upper) {
  const bool has_lower = std::isfinite(lower.value), has_upper = std::isfinite(upper.value);
  std::string range;
  if (has_lower && has_upper) {
    range = std::string("in ") + (lower.open ? "(" : "[") + ToText(lower.value) + ", " +
            ToText(upper.value) + (upper.open ? ")" : "]");
  } else if (has_lower) {
    range = std::string(lower.open ? "> " : ">= ") + ToText(lower.value);
  } else if (has_upper) {
    range = std::string(upper.open ? "< " : "<= ") + ToText(upper.value);
  }
  const std::string expected = has_lower && has_upper ? "a number " + range
                               : range.empty()        ? std::string("a finite number")
                                                      : "a finite number " + range;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        // from_chars, as IntegerIn: no locale, and all of the text or nothing.
        const char* begin = text.data();
        const char* end = text.data() + text.size();
        if (begin != end && *begin == '+') ++begin;  // as CLI11's own conversion takes it
        double value = 0.0;
        const auto [stop, error] = std::from_chars(begin, end, value);
        const bool in = error == std::errc() && stop == end && std::isfinite(value) &&
                        (!has_lower || (lower.open ? value > lower.value : value >= lower.value)) &&
                        (!has_upper || (upper.open ? value < upper.value : value <= upper.value));
        if (!in) {
          const std::string shown = text.size() > 40 ? text.substr(0, 40) + "..." : text;
          return "expected " + expected + ", got \"" + shown + "\"";
        }
        return {};
      },
      range.empty() ? "FLOAT" : "FLOAT " + range);
}

}  // namespace podid::cli
