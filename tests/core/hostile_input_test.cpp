// Hostile and careless input (issue 10 items 5 and 8): a file's bytes reach a
// message only as a short, escaped excerpt; case files are bounded in size
// (also from devices and FIFOs) and in TOML nesting before toml++ sees them.
#include <sys/stat.h>
#include <sys/types.h>

#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>

#include "podid/core/case_file.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::TempDir;

TEST(Escaped, ControlCharactersAndInvalidUtf8AreEscapedUtf8Kept) {
  EXPECT_EQ(Escaped("plain text: 1.5e3 [a]"), "plain text: 1.5e3 [a]");
  EXPECT_EQ(Escaped("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(Escaped("\x1b[31mred\x7f"), "\\x1b[31mred\\x7f");
  EXPECT_EQ(Escaped(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(Escaped("\xc3\xa9t\xc3\xa9 \xe2\x82\xac"), "\xc3\xa9t\xc3\xa9 \xe2\x82\xac");  // été €
  EXPECT_EQ(Escaped("\xc2\x9b" "2J"), "\\xc2\\x9b2J");  // C1 CSI, a terminal control
  EXPECT_EQ(Escaped("\xff\xfe" "a\xc3"), "\\xff\\xfea\\xc3");  // not UTF-8
  EXPECT_EQ(Escaped("\xed\xa0\x80"), "\\xed\\xa0\\x80");       // a surrogate
}

TEST(ReplaceAll, EveryOccurrenceOnceLeftToRight) {
  EXPECT_EQ(ReplaceAll("a min_f b min_f", "min_f", "--fmin"), "a --fmin b --fmin");
  EXPECT_EQ(ReplaceAll("--terms: x", "--terms", "terms"), "terms: x");
  EXPECT_EQ(ReplaceAll("aaa", "a", "aa"), "aaaaaa");  // a replacement is not searched again
  EXPECT_EQ(ReplaceAll("abab", "ab", ""), "");
  EXPECT_EQ(ReplaceAll("none here", "x", "y"), "none here");
}

TEST(Excerpt, ShortQuotedEscapedAndCutOnACharacter) {
  EXPECT_EQ(Excerpt("abc"), "\"abc\"");
  EXPECT_EQ(Excerpt(std::string(100, 'x')), "\"" + std::string(kExcerptBytes, 'x') +
                                                "...\" (100 bytes)");
  EXPECT_EQ(Excerpt("\xc3\xa9\xc3\xa9", 3), "\"\xc3\xa9...\" (4 bytes)");  // not mid-character
  EXPECT_EQ(Excerpt("a\nb", 2), "\"a\\n...\" (3 bytes)");
}

TEST(Escaped, EveryInvalidArgumentMessageIsEscaped) {
  PODID_EXPECT_THROW_WITH(ThrowInvalid("key\n", "x", "\x1b[2J"), std::invalid_argument,
                          "key\\n: expected x, got \\x1b[2J");
  PODID_EXPECT_THROW_WITH(ParseNumber(std::string(200, '9') + "x", "--start"),
                          std::invalid_argument, "...\" (201 bytes)");
}

// Issue 10 item 5: `[force] file = /etc/shadow` printed the file's first line.
TEST(HostileCsv, AFileThatIsNotCsvShowsNoneOfItsContent) {
  const TempDir dir;
  const std::string secret = "root:$6$saltsalt$0123456789abcdefghijklmnopqrstuvwxyz:19000:0:99999:7:::";
  const std::string path = dir.Write("shadow", secret + "\ndaemon:*:19000:0:99999:7:::\n");
  try {
    ReadCsv(path);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("got a first line of " + std::to_string(secret.size()) +
                           " bytes without a comma"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find("root:"), std::string::npos) << message;
    EXPECT_EQ(message.find("saltsalt"), std::string::npos) << message;
    EXPECT_EQ(message.find("daemon"), std::string::npos) << message;
  }
}

TEST(HostileCsv, ControlCharactersInNamesAreRejectedAndInCellsEscaped) {
  const TempDir dir;
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("h.csv", "t,\x1b[31mw1\n0,1\n1,2\n")),
                          std::invalid_argument,
                          "h.csv:1:3: expected column names without control characters, got "
                          "\"\\x1b[31mw1\"");
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("c.csv", "t,w1\n0,1\n1,\x1b[2Jx\n")),
                          std::invalid_argument,
                          "c.csv:3:3: expected a number in column w1, got \"\\x1b[2Jx\"");
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("o.csv", "t" + std::string(60, ' ') + "\n0\n")),
                          std::invalid_argument, "got only \"t\"");
}

TEST(HostileCase, TomlStringsAndKeysInMessagesAreShortAndEscaped) {
  const std::string text =
      "[beam]\nlength = 1\nelements = 2\nyoungs_modulus = 1\ndensity = 1\narea = 1\n"
      "[time]\nduration = 1\nstep = 0.1\n[damping]\ntype = \"\\u001b[31mbad\\nline and a "
      "very long tail of text that goes on and on\"\n";
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse(text, "case.toml").ToSpec(), std::invalid_argument,
                          "case.toml:11: damping.type: expected one of \"rayleigh\", \"none\", "
                          "got \"\\x1b[31mbad\\nline and a very long tail of te...\" (62 bytes)");
  // A key that would set the terminal's title.
  PODID_EXPECT_THROW_WITH(
      CaseDocument::Parse(text + "\"\\u001b]0;title\\u0007\" = 1\n", "case.toml").ToSpec(),
      std::invalid_argument, "case.toml:12: damping.\\x1b]0;title\\x07: expected a key");
}

// Issue 10 item 8: `podid modes /dev/zero` grew to GBs.
TEST(HostileCase, SizeLimitIsCheckedBeforeReadingAll) {
  const TempDir dir;
  const std::string big = dir.Write("big.toml", "# " + std::string(1 << 20, 'x') + "\n");
  PODID_EXPECT_THROW_WITH(CaseDocument::Load(big), std::invalid_argument,
                          "big.toml: expected a case file of at most 1048576 bytes (1 MiB), got "
                          "1048579 bytes");
  const auto start = std::chrono::steady_clock::now();
  PODID_EXPECT_THROW_WITH(CaseDocument::Load("/dev/zero"), std::invalid_argument,
                          "/dev/zero: expected a case file of at most 1048576 bytes (1 MiB), got "
                          "more (a device or a pipe?)");
  // Reading 1 MiB + 1 takes milliseconds; the unbounded read never ended.
  constexpr double kGenerousSeconds = 10.0;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
            kGenerousSeconds);
  PODID_EXPECT_THROW_WITH(CaseDocument::Load(dir.path()), std::invalid_argument,
                          "expected a readable case file, got a folder");
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse(std::string((1 << 20) + 1, '\n'), "text"),
                          std::invalid_argument, "text: expected a case file of at most 1048576");
}

TEST(HostileCase, AFifoWithoutAWriterDoesNotHang) {
  const TempDir dir;
  const std::string fifo = dir.File("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  PODID_EXPECT_THROW_WITH(CaseDocument::Load(fifo).ToSpec(), std::invalid_argument,
                          "beam: expected a [beam] table, got nothing");
}

// Issue 10 item 8: a 40,000-level dotted key overflowed toml++'s stack and
// 16,000 levels took 14 s. The depth is bounded before parsing.
TEST(HostileCase, TomlNestingIsBoundedBeforeParsing) {
  std::string key = "a";
  for (int i = 1; i < 40'000; ++i) key += ".a";
  const auto start = std::chrono::steady_clock::now();
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse("[beam]\n" + key + " = 1\n", "deep.toml"),
                          std::invalid_argument,
                          "deep.toml:2: expected TOML nested at most 32 levels deep (dotted keys, "
                          "tables, arrays and inline tables together), got deeper nesting");
  constexpr double kGenerousSeconds = 2.0;  // a linear scan of 80 kB
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
            kGenerousSeconds);
  const std::string arrays = "x = " + std::string(33, '[') + std::string(33, ']') + "\n";
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse(arrays, "a.toml"), std::invalid_argument,
                          "a.toml:1: expected TOML nested at most 32 levels deep");
  std::string tables = "x = ";
  for (int i = 0; i < 40; ++i) tables += "{ a = ";
  tables += "1" + std::string(40, '}') + "\n";
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse(tables, "t.toml"), std::invalid_argument,
                          "t.toml:1: expected TOML nested at most 32 levels deep");
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse("[" + key + "]\n", "h.toml"), std::invalid_argument,
                          "h.toml:1: expected TOML nested");
  // Dots and brackets inside strings and comments are not nesting.
  const std::string quoted = "x = \"" + key + "[[[[\" # " + key + "\ny = '''\n" + key + "\n'''\n";
  PODID_EXPECT_THROW_WITH(CaseDocument::Parse(quoted, "q.toml").ToSpec(), std::invalid_argument,
                          "q.toml:1: x: expected a key");
  // --set values go through the same check.
  CaseDocument document = CaseDocument::Load(testing::ExamplePath("beam.toml"));
  PODID_EXPECT_THROW_WITH(document.Set("beam.length", std::string(100, '[')),
                          std::invalid_argument, "expected TOML nested at most 32 levels deep");
}

}  // namespace
}  // namespace podid
