#pragma once
// A fresh folder under $TMPDIR (or /tmp) for one test, removed with its content.

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace podid::testing {

class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "podid_test_XXXXXX").string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (::mkdtemp(buffer.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = buffer.data();
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::add, ignored);
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::string& path() const { return path_; }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  /// Writes `text` to `name` in this folder and returns its path.
  std::string Write(const std::string& name, const std::string& text) const {
    const std::string file = File(name);
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }
  /// Names of the entries of the folder.
  std::vector<std::string> Entries() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) {
      names.push_back(entry.path().filename().string());
    }
    return names;
  }

 private:
  std::string path_;
};

/// For a death test in the "threadsafe" style, declared before EXPECT_EXIT:
/// that style runs the whole test again in a new process, whose own TempDirs
/// outlive it (it ends by _Exit or a signal, without destructors). The child
/// inherits TMPDIR, set here to a folder of this one's, so its folders are
/// created there and removed with it; TMPDIR is restored afterwards.
class DeathTestTempRoot {
 public:
  DeathTestTempRoot() {
    if (const char* old = std::getenv("TMPDIR")) saved_ = old;
    // Searchable by all: a child that drops root's privileges must reach its folder.
    std::filesystem::permissions(
        root_.path(), std::filesystem::perms::group_exec | std::filesystem::perms::others_exec,
        std::filesystem::perm_options::add);
    ::setenv("TMPDIR", root_.path().c_str(), 1);
  }
  ~DeathTestTempRoot() {
    if (saved_) {
      ::setenv("TMPDIR", saved_->c_str(), 1);
    } else {
      ::unsetenv("TMPDIR");
    }
  }
  DeathTestTempRoot(const DeathTestTempRoot&) = delete;
  DeathTestTempRoot& operator=(const DeathTestTempRoot&) = delete;

 private:
  TempDir root_;  // destroyed after the destructor's body has restored TMPDIR
  std::optional<std::string> saved_;
};

inline std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace podid::testing
