// Tests of rove::IniFile on small hand-written documents. Expected values
// follow MRPT's CConfigFile (MRPT 2.5.8), confirmed against the library
// where the rules are subtle; differences rove makes on purpose are named.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/ini.h"

namespace {

using rove::ConfigError;
using rove::IniFile;
using rove::ParseError;
using Strings = std::vector<std::string>;

// The ConfigError thrown by `f`.
template <typename F>
ConfigError config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "no ConfigError";
  return ConfigError("", "", "", "");
}

// The ParseError thrown when parsing `text`.
ParseError parse_error(const std::string& text, const std::string& source = "test.ini") {
  try {
    IniFile::parse(text, source);
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError for:\n" << text;
  return ParseError({}, "");
}

TEST(Ini, SectionsKeysAndValues) {
  const auto ini = IniFile::parse(
      "# comment\n"
      "global = 7\n"
      "[ICP]\n"
      "maxIterations = 80\n"
      "thresholdDist=0.75\n"
      "  ; indented comment\n"
      "// slash comment\n"
      "\n"
      "[ Mapping App ]\n"
      "rawlog_file = ../datasets/my file.rawlog\n"
      "empty =\n");
  EXPECT_EQ(ini.sections(), (Strings{"", "ICP", "Mapping App"}));
  EXPECT_EQ(ini.keys("ICP"), (Strings{"maxIterations", "thresholdDist"}));
  EXPECT_EQ(ini.get<int>("", "global"), 7);
  EXPECT_EQ(ini.get<int>("ICP", "maxIterations"), 80);
  EXPECT_DOUBLE_EQ(ini.get<double>("ICP", "thresholdDist"), 0.75);
  EXPECT_EQ(ini.get<std::string>("Mapping App", "rawlog_file"), "../datasets/my file.rawlog");
  EXPECT_EQ(ini.get<std::string>("Mapping App", "empty"), "");
  EXPECT_EQ(ini.line("ICP", "thresholdDist"), 5u);
  EXPECT_FALSE(ini.line("ICP", "nope").has_value());
  EXPECT_TRUE(ini.keys("nope").empty());
  EXPECT_EQ(ini.source(), "<string>");
}

TEST(Ini, NamesAreCaseInsensitiveAndKeepFirstSpelling) {
  // As SimpleIni (SI_NoCase): [Sec] and [sec] merge; a repeated key keeps its
  // first position and spelling and takes the last value.
  const auto ini = IniFile::parse(
      "[Sec]\nAlpha = 1\nbeta = 2\nalpha = 3\n[other]\nx = 0\n[SEC]\nBETA = 4\ngamma = 5\n");
  EXPECT_EQ(ini.sections(), (Strings{"Sec", "other"}));
  EXPECT_EQ(ini.keys("sec"), (Strings{"Alpha", "beta", "gamma"}));
  EXPECT_EQ(ini.get<int>("SEC", "ALPHA"), 3);
  EXPECT_EQ(ini.get<int>("sEc", "Beta"), 4);
  EXPECT_EQ(ini.line("sec", "alpha"), 4u);
  EXPECT_TRUE(ini.has_section("OTHER"));
}

TEST(Ini, EmptySectionNameIsTheGlobalSection) {
  const auto ini = IniFile::parse("[a]\nx = 1\n[]\ng = 2\n");
  EXPECT_EQ(ini.sections(), (Strings{"", "a"}));
  EXPECT_EQ(ini.get<int>("", "g"), 2);
}

TEST(Ini, TrailingComments) {
  const auto ini = IniFile::parse(
      "[s]\n"
      "a = 80    // max iterations\n"
      "b = 0.05 # cell size\n"
      "c = 1\t\t;number of maps\n"
      "d = http://example.org/x  // url\n"
      "e = a//b // c\n"
      "f = #fff\n"
      "g = [1 2 ; 3 4]  ; matrix\n"
      "h = 1.5;\n"
      "i = 0.10// no space, after a number\n"
      "j = text// no space, not a number\n"
      "k = //starts with slashes\n");
  EXPECT_EQ(ini.get<int>("s", "a"), 80);
  EXPECT_DOUBLE_EQ(ini.get<double>("s", "b"), 0.05);
  EXPECT_EQ(ini.get<int>("s", "c"), 1);
  EXPECT_EQ(ini.get<std::string>("s", "d"), "http://example.org/x");
  EXPECT_EQ(ini.get<std::string>("s", "e"), "a//b");
  EXPECT_EQ(ini.get<std::string>("s", "f"), "#fff");
  EXPECT_EQ(ini.get<std::string>("s", "g"), "[1 2 ; 3 4]");
  EXPECT_DOUBLE_EQ(ini.get<double>("s", "h"), 1.5);
  EXPECT_DOUBLE_EQ(ini.get<double>("s", "i"), 0.10);
  EXPECT_EQ(ini.get<std::string>("s", "j"), "text// no space, not a number");
  EXPECT_EQ(ini.get<std::string>("s", "k"), "//starts with slashes");
}

TEST(Ini, RawIsWhatMrptReadStringReturns) {
  // Values MRPT 2.5.8's read_string returned for the same lines.
  const auto ini = IniFile::parse(
      "[s]\ne = a//b // c\nb = 0.05 # cell size\nc = 1\t\t;n\nd = 5   // five\nh = 1.5;\n");
  EXPECT_EQ(ini.raw("s", "e"), "a//b // c");  // MRPT looks only at the first "//"
  EXPECT_EQ(ini.raw("s", "b"), "0.05 # cell size");
  EXPECT_EQ(ini.raw("s", "c"), "1\t\t;n");
  EXPECT_EQ(ini.raw("s", "d"), "5");
  EXPECT_EQ(ini.raw("s", "h"), "1.5;");
}

TEST(Ini, Booleans) {
  const auto ini = IniFile::parse(
      "[b]\nt1 = true\nt2 = YES\nt3 = On\nt4 = 1\nf1 = False\nf2 = no\nf3 = OFF\nf4 = 0\n"
      "bad1 = 2\nbad2 = truthy\n");
  for (const char* k : {"t1", "t2", "t3", "t4"}) EXPECT_TRUE(ini.get<bool>("b", k)) << k;
  for (const char* k : {"f1", "f2", "f3", "f4"}) EXPECT_FALSE(ini.get<bool>("b", k)) << k;
  EXPECT_THROW(ini.get<bool>("b", "bad1"), ConfigError);
  EXPECT_THROW(ini.get<bool>("b", "bad2"), ConfigError);
}

TEST(Ini, Integers) {
  const auto ini = IniFile::parse(
      "[n]\na = 42\nb = +42\nc = -7\nd = 0x00BFFF\ne = 1.0\nf = 12abc\ng = 3000000000\n"
      "h = -1\ni = 18446744073709551615\nj = -9223372036854775808\nk = 9223372036854775808\n"
      "l = -2147483648\nm = - 5\nn = --5\no = 0x-5\n");
  EXPECT_EQ(ini.get<int>("n", "a"), 42);
  EXPECT_EQ(ini.get<int>("n", "b"), 42);
  EXPECT_EQ(ini.get<int>("n", "c"), -7);
  EXPECT_EQ(ini.get<int>("n", "d"), 0xBFFF);
  EXPECT_THROW(ini.get<int>("n", "e"), ConfigError);
  EXPECT_THROW(ini.get<int>("n", "f"), ConfigError);
  EXPECT_THROW(ini.get<int>("n", "g"), ConfigError);
  EXPECT_EQ(ini.get<std::int64_t>("n", "g"), 3000000000LL);
  EXPECT_EQ(ini.get<unsigned>("n", "g"), 3000000000u);
  EXPECT_THROW(ini.get<unsigned>("n", "h"), ConfigError);
  EXPECT_EQ(ini.get<std::uint64_t>("n", "i"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_THROW(ini.get<std::int64_t>("n", "i"), ConfigError);
  EXPECT_EQ(ini.get<std::int64_t>("n", "j"), std::numeric_limits<std::int64_t>::min());
  EXPECT_THROW(ini.get<std::int64_t>("n", "k"), ConfigError);
  EXPECT_EQ(ini.get<int>("n", "l"), std::numeric_limits<int>::min());
  EXPECT_THROW(ini.get<int>("n", "m"), ConfigError);
  EXPECT_THROW(ini.get<int>("n", "n"), ConfigError);
  EXPECT_THROW(ini.get<int>("n", "o"), ConfigError);
}

TEST(Ini, FloatingPoint) {
  const auto ini = IniFile::parse(
      "[f]\na = 1e-3\nb = .5\nc = -2.5E+2\nd = inf\ne = nan\nf = 1e999\ng = 1.5x\nh = 1e39\n"
      "i = abc\nj = 0x10\nk =\n");
  EXPECT_DOUBLE_EQ(ini.get<double>("f", "a"), 1e-3);
  EXPECT_DOUBLE_EQ(ini.get<double>("f", "b"), 0.5);
  EXPECT_DOUBLE_EQ(ini.get<double>("f", "c"), -250.0);
  EXPECT_EQ(ini.get<double>("f", "d"), std::numeric_limits<double>::infinity());
  EXPECT_THROW(ini.get<double>("f", "e"), ConfigError);
  EXPECT_THROW(ini.get<double>("f", "f"), ConfigError);
  EXPECT_THROW(ini.get<double>("f", "g"), ConfigError);
  EXPECT_DOUBLE_EQ(ini.get<double>("f", "h"), 1e39);
  EXPECT_THROW(ini.get<float>("f", "h"), ConfigError);
  EXPECT_FLOAT_EQ(ini.get<float>("f", "c"), -250.0f);
  EXPECT_THROW(ini.get<double>("f", "i"), ConfigError);
  EXPECT_DOUBLE_EQ(ini.get<double>("f", "j"), 16.0);
  EXPECT_THROW(ini.get<double>("f", "k"), ConfigError);
}

TEST(Ini, ErrorsNameFileSectionKeyAndLine) {
  const auto ini = IniFile::parse("[ICP]\n\nmaxIterations = abc\nthr = 1e999\n", "demo.ini");
  auto e = config_error([&] { ini.get<double>("ICP", "maxIterations"); });
  EXPECT_EQ(e.file(), "demo.ini");
  EXPECT_EQ(e.section(), "ICP");
  EXPECT_EQ(e.key(), "maxIterations");
  EXPECT_EQ(std::string(e.what()), "demo.ini: [ICP] maxIterations: line 3: 'abc' is not a double");
  e = config_error([&] { ini.get<double>("ICP", "thr"); });
  EXPECT_EQ(std::string(e.what()), "demo.ini: [ICP] thr: line 4: '1e999' is out of range for a double");
  e = config_error([&] { ini.get<int>("ICP", "missing"); });
  EXPECT_EQ(std::string(e.what()), "demo.ini: [ICP] missing: missing key");
  e = config_error([&] { ini.get<int>("Nope", "x"); });
  EXPECT_EQ(std::string(e.what()), "demo.ini: [Nope] x: missing key (no section [Nope])");
}

TEST(Ini, GetOrReturnsFallbackOnlyWhenMissing) {
  const auto ini = IniFile::parse("[s]\nbad = x\nname = icp\n");
  EXPECT_EQ(ini.get_or("s", "absent", 5), 5);
  EXPECT_DOUBLE_EQ(ini.get_or("s", "absent", 2.5), 2.5);
  EXPECT_EQ(ini.get_or("s", "absent", "dflt"), "dflt");
  EXPECT_EQ(ini.get_or("s", "name", "dflt"), "icp");
  EXPECT_EQ(ini.get_or("nosection", "absent", true), true);
  EXPECT_THROW(ini.get_or("s", "bad", 5), ConfigError);
}

TEST(Ini, Vectors) {
  const auto ini = IniFile::parse(
      "[v]\na = [1 2 3]\nb = [1, 2, 3]\nc = 1 2 3\nd = [ ]\ne =\nf = [1 2\ng = [1 [2]]\n"
      "h = 1 x 3\ni = [a, bb,c]\nj = 1,,2\n");
  const std::vector<double> expected{1, 2, 3};
  EXPECT_EQ(ini.get_vector<double>("v", "a"), expected);
  EXPECT_EQ(ini.get_vector<double>("v", "b"), expected);
  EXPECT_EQ(ini.get_vector<double>("v", "c"), expected);
  EXPECT_EQ(ini.get_vector<int>("v", "c"), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(ini.get_vector<double>("v", "d").empty());
  EXPECT_TRUE(ini.get_vector<double>("v", "e").empty());
  EXPECT_EQ(ini.get_vector<double>("v", "j"), (std::vector<double>{1, 2}));  // as MRPT's tokenize
  EXPECT_THROW(ini.get_vector<double>("v", "f"), ConfigError);
  EXPECT_THROW(ini.get_vector<double>("v", "g"), ConfigError);
  const auto e = config_error([&] { ini.get_vector<double>("v", "h"); });
  EXPECT_EQ(std::string(e.what()), "<string>: [v] h: line 9: element 1: 'x' is not a double");
  EXPECT_EQ(ini.get_vector<std::string>("v", "i"), (Strings{"a", "bb", "c"}));
}

TEST(Ini, Matrices) {
  const auto ini = IniFile::parse(
      "[m]\na = [1 2 3; 4 5 6]\nb = [1, 2 ; 3, 4]  ; comment\nc = []\nd = [1 2; 3]\ne = [1 2;]\n"
      "f = 7\n");
  EXPECT_EQ(ini.get_matrix<double>("m", "a"),
            (std::vector<std::vector<double>>{{1, 2, 3}, {4, 5, 6}}));
  EXPECT_EQ(ini.get_matrix<int>("m", "b"), (std::vector<std::vector<int>>{{1, 2}, {3, 4}}));
  EXPECT_TRUE(ini.get_matrix<double>("m", "c").empty());
  const auto e = config_error([&] { ini.get_matrix<double>("m", "d"); });
  EXPECT_EQ(std::string(e.what()), "<string>: [m] d: line 5: row 1 has 1 elements, row 0 has 2");
  EXPECT_THROW(ini.get_matrix<double>("m", "e"), ConfigError);
  EXPECT_EQ(ini.get_matrix<double>("m", "f"), (std::vector<std::vector<double>>{{7}}));
}

enum class IcpMethod { Classic = 0, LevenbergMarquardt = 1 };

TEST(Ini, Enums) {
  const auto ini = IniFile::parse(
      "[e]\na = icpClassic\nb = ICPLEVENBERGMARQUARDT  // comment\nc = 1\nd = 5\ne = other\n");
  const auto read = [&](const char* key) {
    return ini.get_enum<IcpMethod>("e", key, {{"icpClassic", IcpMethod::Classic},
                                              {"icpLevenbergMarquardt", IcpMethod::LevenbergMarquardt}});
  };
  EXPECT_EQ(read("a"), IcpMethod::Classic);
  EXPECT_EQ(read("b"), IcpMethod::LevenbergMarquardt);
  EXPECT_EQ(read("c"), IcpMethod::LevenbergMarquardt);
  EXPECT_THROW(read("d"), ConfigError);
  const auto e = config_error([&] { read("e"); });
  EXPECT_EQ(std::string(e.what()),
            "<string>: [e] e: line 6: 'other' is not one of: icpClassic (0), "
            "icpLevenbergMarquardt (1)");
}

TEST(Ini, UnreadKeysListsWhatNoGetterTouched) {
  const auto ini = IniFile::parse("[s]\na = 1\nb = 2\nc = 3\nd = 4\ne = [1]\nf = x\n");
  EXPECT_EQ(ini.unread_keys("s"), (Strings{"a", "b", "c", "d", "e", "f"}));
  (void)ini.get<int>("s", "B");
  (void)ini.has("s", "c");  // not a read
  (void)ini.get_or("s", "d", 0);
  (void)ini.get_or("s", "zz", 0);  // missing: nothing to mark
  (void)ini.get_vector<int>("s", "e");
  (void)ini.raw("s", "f");
  EXPECT_EQ(ini.unread_keys("s"), (Strings{"a", "c"}));
  const IniFile copy = ini;  // read marks are copied
  EXPECT_EQ(copy.unread_keys("s"), (Strings{"a", "c"}));
  // A malformed value still counts as read: the key is known, its value bad.
  const auto bad = IniFile::parse("[s]\nx = abc\n");
  EXPECT_THROW(bad.get<int>("s", "x"), ConfigError);
  EXPECT_TRUE(bad.unread_keys("s").empty());
}

TEST(Ini, DefinesVariablesAndEval) {
  ::setenv("ROVE_INI_TEST_VAR", "from-env", 1);
  ::unsetenv("ROVE_INI_TEST_UNSET");
  const auto ini = IniFile::parse(
      "@define ROBOT_MAX_V  1.0\n"
      "@define W 60 // degrees\n"
      "@define TWICE $eval{2*ROBOT_MAX_V}\n"
      "[nav]\n"
      "v = ${ROBOT_MAX_V}   // m/s\n"
      "w = $eval{W*pi/180}\n"
      "both = ${ROBOT_MAX_V}, ${W}\n"
      "twice = ${TWICE}\n"
      "env = $env{ROVE_INI_TEST_VAR}/x\n"
      "unset = [$env{ROVE_INI_TEST_UNSET}]\n"
      "# @define COMMENTED 1  and ${UNDEFINED} are not processed in comments\n",
      "<string>");
  EXPECT_DOUBLE_EQ(ini.get<double>("nav", "v"), 1.0);
  EXPECT_EQ(ini.get<std::string>("nav", "w"), "1.047198e+00");  // printf %e, as MRPT
  EXPECT_EQ(ini.get<std::string>("nav", "both"), "1.0, 60");     // the define's comment is cut
  EXPECT_EQ(ini.raw("nav", "both"), "1.0, 60");                   // MRPT cuts it too
  EXPECT_EQ(ini.get<std::string>("nav", "twice"), "2.000000e+00");
  EXPECT_EQ(ini.get<std::string>("nav", "env"), "from-env/x");
  EXPECT_EQ(ini.get<std::string>("nav", "unset"), "[]");
  EXPECT_FALSE(ini.has("nav", "COMMENTED"));
  EXPECT_EQ(ini.line("nav", "v"), 5u);
}

TEST(Ini, PreprocessorErrorsNameTheLine) {
  auto e = parse_error("[s]\na = 1\nb = ${NOPE}\n");
  EXPECT_EQ(e.location().source, "test.ini");
  EXPECT_EQ(e.location().line, 3u);
  EXPECT_EQ(e.problem(), "unknown variable 'NOPE' (not @define'd above)");
  e = parse_error("[s]\nb = ${OPEN\n");
  EXPECT_EQ(e.location().line, 2u);
  EXPECT_EQ(e.problem(), "missing closing '}'");
  e = parse_error("@define X abc\n[s]\nb = $eval{X+1}\n");
  EXPECT_EQ(e.location().line, 3u);
  EXPECT_EQ(e.problem(), "unknown name 'X'");
  e = parse_error("[s]\nb = $eval{1/0}\n");
  EXPECT_EQ(e.problem(), "result is not finite");
  // The $eval body ends at the first '}', as in MRPT: no $env{} inside it.
  e = parse_error("[s]\nb = $eval{$env{HOME}+1}\n");
  EXPECT_EQ(e.problem(), "unexpected '$'");
  e = parse_error("@define\n");
  EXPECT_EQ(e.problem(), "@define needs a name");
  e = parse_error("@defineX 1\n");
  EXPECT_EQ(e.problem(), "expected a space after @define");
}

TEST(Ini, LineContinuation) {
  const auto ini = IniFile::parse(
      "[s]\n"
      "formula = 1/(1+x^2) \\\n"
      "\t+ 2\n"
      "after = 1\n"
      "crlf = a\\\r\nb\r\n"
      "last = end\\");
  // As MRPT: backslash and line break vanish, nothing is inserted.
  EXPECT_EQ(ini.get<std::string>("s", "formula"), "1/(1+x^2) \t+ 2");
  EXPECT_EQ(ini.line("s", "after"), 4u);
  EXPECT_EQ(ini.get<std::string>("s", "crlf"), "ab");
  EXPECT_EQ(ini.get<std::string>("s", "last"), "end\\");
  // A continued comment swallows the next line.
  const auto c = IniFile::parse("[s]\n# comment \\\nhidden = 1\nshown = 2\n");
  EXPECT_EQ(c.keys("s"), (Strings{"shown"}));
  // Errors after a continuation report the physical line.
  EXPECT_EQ(parse_error("[s]\na = 1 \\\n 2\noops\n").location().line, 4u);
}

TEST(Ini, LineEndingsAndByteOrderMark) {
  const auto ini = IniFile::parse("\xEF\xBB\xBF[s]\r\na = 1\r\nb = 2\rc = 3");
  EXPECT_EQ(ini.keys("s"), (Strings{"a", "b", "c"}));
  EXPECT_EQ(ini.get<int>("s", "c"), 3);
  EXPECT_EQ(ini.line("s", "c"), 4u);
}

TEST(Ini, MalformedLinesAreParseErrors) {
  struct Case {
    std::string text;
    std::size_t line;
    std::string problem;
  };
  const Case cases[] = {
      {"[a]\nx = 1\n[section\ny = 2\n", 3, "unterminated section header (missing ']')"},
      {"[a]\nx = 1\nrandom seed\n", 3, "expected 'key = value', '[section]' or a comment"},
      {"[a]\n= 5\n", 2, "empty key before '='"},
      {"[a] junk\n", 1, "unexpected text after section header: 'junk'"},
      {std::string("[a]\nx = 1\0y\n", 12), 2, "NUL byte in text"},
  };
  for (const auto& c : cases) {
    const auto e = parse_error(c.text, "bad.ini");
    EXPECT_EQ(e.location().source, "bad.ini");
    EXPECT_EQ(e.location().line, c.line) << c.text;
    EXPECT_EQ(e.problem(), c.problem) << c.text;
  }
  // Trailing comments after a section header are fine.
  EXPECT_NO_THROW(IniFile::parse("[a] // ok\n[b] # ok\n[c] ; ok\n"));
}

TEST(Ini, NonStrictSkipsMalformedLinesLikeMrpt) {
  rove::IniOptions lenient;
  lenient.strict = false;
  const auto ini = IniFile::parse("[a]\nx = 1\nrandom seed\n= 5\n[b] junk\ny = 2\n[open\nz = 3\n",
                                  "lenient.ini", lenient);
  EXPECT_EQ(ini.get<int>("a", "x"), 1);
  EXPECT_EQ(ini.get<int>("b", "y"), 2);
  EXPECT_EQ(ini.get<int>("b", "z"), 3);  // "[open" skipped: still in [b]
  ASSERT_EQ(ini.skipped_lines().size(), 4u);
  EXPECT_EQ(ini.skipped_lines()[0].line, 3u);
  EXPECT_EQ(ini.skipped_lines()[0].text, "random seed");
  EXPECT_EQ(ini.skipped_lines()[1].line, 4u);
  EXPECT_EQ(ini.skipped_lines()[2].line, 5u);
  EXPECT_EQ(ini.skipped_lines()[3].line, 7u);
}

TEST(Ini, LoadReadsFilesAndReportsMissingOnes) {
  EXPECT_THROW(IniFile::load("/nonexistent/rove/test.ini"), rove::IoError);
  const std::string path = ::testing::TempDir() + "rove_ini_test.ini";
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("[s]\nk = 3\nbad\n", f);
    std::fclose(f);
  }
  try {
    IniFile::load(path);
    FAIL() << "no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, path);
    EXPECT_EQ(e.location().line, 3u);
  }
  rove::IniOptions lenient;
  lenient.strict = false;
  const auto ini = IniFile::load(path, lenient);
  EXPECT_EQ(ini.source(), path);
  EXPECT_EQ(ini.get<int>("s", "k"), 3);
  EXPECT_THROW(ini.get<int>("s", "nope"), ConfigError);
  std::remove(path.c_str());
}

TEST(Ini, ToStringRoundTrips) {
  const auto ini = IniFile::parse(
      "top = 1\n[ICP]\nmaxIterations = 80 // c\nshape = [1 2; 3 4]\n[Other]\nurl = http://x/y\n"
      "[Empty]\n");
  const std::string text = ini.to_string();
  EXPECT_EQ(text,
            "top = 1\n\n[ICP]\nmaxIterations = 80\nshape = [1 2; 3 4]\n\n[Other]\nurl = http://x/y\n"
            "\n[Empty]\n");
  const auto back = IniFile::parse(text);
  EXPECT_EQ(back.sections(), ini.sections());
  for (const auto& s : ini.sections()) {
    ASSERT_EQ(back.keys(s), ini.keys(s));
    for (const auto& k : ini.keys(s))
      EXPECT_EQ(back.get<std::string>(s, k), ini.get<std::string>(s, k));
  }
}

TEST(Ini, SetValidatesWhatItCanWrite) {
  IniFile ini;
  ini.set("ICP", "maxIterations", "80");
  ini.set("ICP", "MAXITERATIONS", "90");
  ini.set("", "g", "x y");
  EXPECT_EQ(ini.get<int>("icp", "maxiterations"), 90);
  EXPECT_EQ(ini.line("ICP", "maxIterations"), 0u);
  EXPECT_EQ(ini.to_string(), "g = x y\n\n[ICP]\nmaxIterations = 90\n");
  EXPECT_THROW(ini.set("s", "k", "a // b"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "k", " lead"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "k", "x;"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "k", "two\nlines"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "k", "${X}"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "k", "ends\\"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "", "v"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "a=b", "v"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s", "#k", "v"), rove::InvalidArgument);
  EXPECT_THROW(ini.set("s]", "k", "v"), rove::InvalidArgument);
}

TEST(Ini, ToStringRejectsValuesItCannotWriteBack) {
  ::setenv("ROVE_INI_TEST_TRICKY", "${X}", 1);
  const auto ini = IniFile::parse("[s]\nk = $env{ROVE_INI_TEST_TRICKY}\n");
  EXPECT_EQ(ini.get<std::string>("s", "k"), "${X}");  // not expanded again
  EXPECT_THROW((void)ini.to_string(), rove::InvalidArgument);
}

}  // namespace

namespace {

// Regression: a repeated key or section was silently last-wins; both are
// now recorded with their lines so that `rove config check` can warn.
TEST(Ini, DuplicateKeysAndSectionsAreRecorded) {
  const auto ini = IniFile::parse(
      "[ICP]\nmaxIterations = 80\nthresholdDist = 0.75\n[other]\nx = 1\n[icp]\nMAXITERATIONS = 5\n"
      "maxIterations = 7\n",
      "dup.ini");
  EXPECT_EQ(ini.get<int>("ICP", "maxIterations"), 7);  // MRPT's rule: the last value
  const auto& d = ini.duplicates();
  ASSERT_EQ(d.size(), 3u);
  EXPECT_TRUE(d[0].is_section);
  EXPECT_EQ(d[0].section, "icp");
  EXPECT_EQ(d[0].line, 6u);
  EXPECT_EQ(d[0].first_line, 1u);
  EXPECT_FALSE(d[1].is_section);
  EXPECT_EQ(d[1].section, "ICP");
  EXPECT_EQ(d[1].key, "MAXITERATIONS");
  EXPECT_EQ(d[1].line, 7u);
  EXPECT_EQ(d[1].first_line, 2u);
  EXPECT_EQ(d[2].key, "maxIterations");
  EXPECT_EQ(d[2].line, 8u);
  EXPECT_EQ(d[2].first_line, 7u);
  EXPECT_TRUE(IniFile::parse("[a]\nx = 1\n[b]\nx = 2\n").duplicates().empty());
}

// Regression: reading /dev/zero or /dev/urandom as a config grew to
// gigabytes; devices, FIFOs and directories are refused by name.
TEST(Ini, DevZeroAsConfigIsRefused) {
  for (const char* dev : {"/dev/zero", "/dev/urandom"}) {
    try {
      (void)IniFile::load(dev);
      ADD_FAILURE() << dev;
    } catch (const rove::IoError& e) {
      EXPECT_NE(std::string(e.what()).find(dev), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)IniFile::load("/tmp"), rove::IoError);
}

}  // namespace
