// The case parser's table reader (case/toml_reader.hpp): every error names the file, the line
// and the key path; unknown keys are reported with the nearest valid one.
#include "talus/case/toml_reader.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <string_view>

using namespace talus;
using namespace talus::case_reading;

namespace {

// The CaseError message of f(reader) on the table [material] parsed from `text`; "" if none.
std::string error_of(const std::string& text, const std::function<void(TableReader&)>& f) {
  const toml::table doc = toml::parse(std::string_view(text), std::string_view("case.toml"));
  TableReader r(*doc["material"].as_table(), "material", Where{"case.toml"});
  try {
    f(r);
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(TableReader, ValuesAndFallbacks) {
  const std::string text = "[material]\nE = 2e9\nn = 3\nname = 'rock'\nv = [1, 2.5]\n";
  const toml::table doc = toml::parse(std::string_view(text), std::string_view("case.toml"));
  TableReader r(*doc["material"].as_table(), "material", Where{"case.toml"});
  EXPECT_EQ(r.number("E"), 2e9);
  EXPECT_EQ(r.number("missing", 7.0), 7.0);
  EXPECT_EQ(r.integer("n", 1, 1, 8), 3);
  EXPECT_EQ(r.name("name", ""), "rock");
  const Vec3a v = r.vector("v", 2);
  EXPECT_EQ(v[0], 1.0);
  EXPECT_EQ(v[1], 2.5);
  EXPECT_FALSE(r.optional_number("other").has_value());
  EXPECT_NO_THROW(r.finish()); // every key was asked for
}

TEST(TableReader, ErrorsNameFileLineAndKey) {
  const std::string text = "[material]\nE = 2e9\nn = 9\nname = 5\nv = [1]\nx = 'a'\n";
  EXPECT_EQ(error_of(text, [](TableReader& r) { r.integer("n", 1, 1, 8); }),
            "case.toml:3: material.n: must be in [1, 8], got 9");
  EXPECT_EQ(error_of(text, [](TableReader& r) { r.string("name"); }),
            "case.toml:4: material.name: expected a string, got an integer");
  EXPECT_NE(error_of(text, [](TableReader& r) { r.vector("v", 2); })
                .find("case.toml:5: material.v: expected an array of 2 numbers"),
            std::string::npos);
  EXPECT_EQ(error_of(text, [](TableReader& r) { r.number("x"); }),
            "case.toml:6: material.x: expected a number, got a string");
  // An integer beyond int is refused before narrowing (2^32 + 2 is not 2).
  EXPECT_EQ(
      error_of("[material]\nn = 4294967298\n", [](TableReader& r) { r.integer("n", 1, 1, 8); }),
      "case.toml:2: material.n: must be in [1, 8], got 4294967298");
}

// A key nobody asked for is reported with the nearest valid key; a missing key points at a
// present key that looks like a misspelling of it.
TEST(TableReader, UnknownAndMissingKeys) {
  const std::string text = "[material]\ndensity = 2000\nyoungs = 1e9\n";
  const std::string unknown = error_of(text, [](TableReader& r) {
    r.number("density");
    r.number("young", 1e8);
    r.finish();
  });
  EXPECT_NE(unknown.find("case.toml:3: material.youngs: unknown key"), std::string::npos)
      << unknown;
  EXPECT_NE(unknown.find("did you mean 'young'"), std::string::npos) << unknown;
  const std::string missing = error_of(text, [](TableReader& r) { r.number("young"); });
  EXPECT_NE(missing.find("material.young: required key is missing (line 3 has 'youngs')"),
            std::string::npos)
      << missing;
  // A key of another model is named as such, not as unknown.
  const std::string elsewhere = error_of(text, [](TableReader& r) {
    r.number("density");
    r.belongs_elsewhere("youngs", "a key of the other model");
    r.finish();
  });
  EXPECT_NE(elsewhere.find("material.youngs: a key of the other model"), std::string::npos)
      << elsewhere;
}

// A control character in a string (a terminal escape, a NUL) is refused, naming its byte.
TEST(TableReader, StringsArePrintable) {
  const std::string e =
      error_of("[material]\nname = \"a\\u001b[31mb\"\n", [](TableReader& r) { r.string("name"); });
  EXPECT_NE(e.find("case.toml:2: material.name: holds a control character (byte 2"),
            std::string::npos)
      << e;
}
