// The case file: a good case maps onto Case; each bad case gets its message with the file, the
// line and the key path, and a suggestion where a key is misspelt.
#include "talus/case/geometry.hpp"
#include "talus/case/parse.hpp"
#include "talus/setup/seeds.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

const std::string good = R"(title = "block"
[simulation]
dimension = 2
end_time = 1.0
gravity = [0, -9.81]
scheme = "usl"
flip = 0.95
[grid]
origin = [-1, 0]
extent = [4, 2]
cell_size = 0.25
shape_function = "linear"
[grid.boundary]
y_min = "fixed"
x_min = "slip"
[[material]]
name = "rock"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.25
[[body]]
name = "block"
material = "rock"
box = { min = [0, 0], max = [1, 0.5] }
particles_per_cell = 2
[[body]]
name = "ball"
material = "rock"
disk = { center = [2, 1], radius = 0.3 }
[[boundary]]
body = "block"
max = [0.1, 2]
velocity_x = 0.0
[[probe]]
name = "top"
body = "block"
near = [0.5, 0.5]
[output]
every = 0.1
)";

TEST(ParseCase, AGoodCaseMapsOntoTheStruct) {
  const Case c = test::case_from(good);
  EXPECT_EQ(c.title, "block");
  EXPECT_EQ(c.simulation.scheme, Scheme::usl);
  EXPECT_DOUBLE_EQ(c.simulation.flip, 0.95);
  EXPECT_DOUBLE_EQ(c.simulation.gravity[1], -9.81);
  EXPECT_EQ(c.grid.shape, ShapeKind::linear);
  EXPECT_EQ(c.grid.faces[2], FaceCondition::fixed);
  EXPECT_EQ(c.grid.faces[0], FaceCondition::slip);
  EXPECT_EQ(c.grid.faces[1], FaceCondition::free);
  ASSERT_EQ(c.bodies.size(), 2u);
  EXPECT_EQ(c.bodies[1].geometry[0].kind, Geometry::Kind::disk);
  ASSERT_EQ(c.boundaries.size(), 1u);
  EXPECT_TRUE(c.boundaries[0].fixed[0]);
  EXPECT_FALSE(c.boundaries[0].fixed[1]);
  EXPECT_EQ(c.probes[0].body, 0);
  // 1 m x 0.5 m at 0.25 m cells and 2 x 2 per cell: 4 x 2 cells x 4 = 32 particles.
  EXPECT_EQ(count_particles(c, 0), 32u);
}

TEST(ParseCase, OverridesReplaceKeysByPathAndByName) {
  const Case c = test::case_from(good, {"grid.cell_size=0.125", "body.block.particles_per_cell=3",
                                        "simulation.scheme=musl", "material.0.density=2500"});
  EXPECT_DOUBLE_EQ(c.grid.cell_size, 0.125);
  EXPECT_EQ(c.bodies[0].particles_per_cell, 3);
  EXPECT_EQ(c.simulation.scheme, Scheme::musl);
  EXPECT_DOUBLE_EQ(c.materials[0].density(), 2500.0);
  EXPECT_NE(c.text.find("material.0.density=2500"), std::string::npos); // in a [[run]] entry
}

// A key nested deeper than any case needs (a 100,000-deep dotted key crashed the TOML reader)
// is refused at its line; dotted numbers in arrays and dots in strings do not count.
TEST(ParseCase, ADeepDottedKeyIsRefusedAtItsLine) {
  std::string deep = "\n[deep]\n";
  for (int i = 0; i < 100000; ++i)
    deep += "a.";
  deep += "b = 1\n";
  try {
    test::case_from(good + deep);
    FAIL() << "accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("a key nested 100001 tables deep"), std::string::npos)
        << e.what();
  }
  std::string numbers = "\n[[probe]]\nname = \"far\"\nbody = \"block\"\nnear = [\n";
  for (int i = 0; i < 40; ++i)
    numbers += "0.5, "; // 40 dotted numbers on one line of a multi-line array
  numbers += "\n]\n";
  try {
    test::case_from(good + numbers);
  } catch (const CaseError& e) {
    EXPECT_EQ(std::string(e.what()).find("tables deep"), std::string::npos) << e.what();
  }
}

// An error in a value an override set names the override (--set), not a line of the file.
TEST(ParseCase, AnOverridesErrorNamesTheOverride) {
  auto message = [](const std::string& set) {
    try {
      test::case_from(good, {set});
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message("grid.cell_size=\"x\"").find("(from --set) grid.cell_size: expected a number"),
            std::string::npos);
  EXPECT_NE(message("simulation.scheme=usx").find("(from --set) simulation.scheme:"),
            std::string::npos);
  EXPECT_NE(message("body.nosuch.density=1").find("--set body.nosuch.density: no entry"),
            std::string::npos);
}

// The case a run folder keeps: the text as written, then a [[run]] entry of the overrides and of
// the renames to the copies in inputs/. Parsed again from the run folder, it is the same case.
TEST(ParseCase, TheCaseAsRunIsTheTextAsWrittenAndARunEntry) {
  const std::string dir = test::temp_dir("case_as_run");
  std::filesystem::create_directories(dir + "/data");
  std::filesystem::copy_file(std::string(TALUS_SOURCE_DIR) + "/cases/examples/wedge.csv",
                             dir + "/data/wedge.csv");
  const std::string text = "# my comment\n" + good +
                           "[[body]]\nname = \"wedge\"\nmaterial = \"rock\"\n"
                           "polygon = \"data/wedge.csv\"\n";
  const Case c = parse_case_text(text, dir + "/case.toml", {"grid.cell_size=0.125"});
  ASSERT_EQ(c.inputs.size(), 1u);
  EXPECT_EQ(c.inputs[0].source, dir + "/data/wedge.csv");
  EXPECT_EQ(c.inputs[0].copy, "inputs/wedge.csv");
  EXPECT_EQ(c.text.substr(0, text.size()), text); // verbatim, comment and all
  EXPECT_NE(c.text.find("'grid.cell_size=0.125'"), std::string::npos);
  EXPECT_NE(c.text.find("'data/wedge.csv' = 'inputs/wedge.csv'"), std::string::npos);
  EXPECT_NE(c.resolved.find("cell_size = 0.125"), std::string::npos);
  EXPECT_EQ(c.resolved.find("[[run]]"), std::string::npos);

  // The run folder: its case.toml and the copy; parsed there, the same case and no new entry.
  const std::string run = dir + "/run";
  std::filesystem::create_directories(run + "/inputs");
  std::filesystem::copy_file(dir + "/data/wedge.csv", run + "/inputs/wedge.csv");
  const Case again = parse_case_text(c.text, run + "/case.toml");
  EXPECT_EQ(again.text, c.text);
  EXPECT_EQ(again.resolved, c.resolved);
  EXPECT_DOUBLE_EQ(again.grid.cell_size, 0.125);
  EXPECT_EQ(again.bodies[2].geometry[0].vertices, c.bodies[2].geometry[0].vertices);
  EXPECT_EQ(again.inputs[0].source, run + "/inputs/wedge.csv");
  // A later override goes after the earlier ones: it wins.
  const Case later = parse_case_text(c.text, run + "/case.toml", {"grid.cell_size=0.5"});
  EXPECT_DOUBLE_EQ(later.grid.cell_size, 0.5);
  EXPECT_DOUBLE_EQ(parse_case_text(later.text, run + "/case.toml").grid.cell_size, 0.5);
}

// Two files of the same name in different folders get two copies; one file named twice, one.
TEST(ParseCase, InputCopiesHaveDistinctNames) {
  case_reading::InputFiles files("/case");
  EXPECT_EQ(files.resolve("a/s.csv"), "/case/a/s.csv");
  files.resolve("b/s.csv");
  files.resolve("./a/s.csv");
  ASSERT_EQ(files.files().size(), 2u);
  EXPECT_EQ(files.files()[0].copy, "inputs/s.csv");
  EXPECT_EQ(files.files()[1].copy, "inputs/s-2.csv");
  const auto renames = files.renames_to_copies();
  EXPECT_EQ(renames.size(), 3u);
  EXPECT_EQ(renames.at("./a/s.csv"), "inputs/s.csv");
}

TEST(ParseCase, PolygonFromTheVaiontCsv) {
  const auto v = read_polygon_csv(std::string(TALUS_SOURCE_DIR) + "/cases/examples/wedge.csv");
  ASSERT_GE(v.size(), 3u);
  EXPECT_TRUE(point_in_polygon(v, 1.0, 0.2));
  EXPECT_FALSE(point_in_polygon(v, 3.9, 1.9));
}

// law = "surface" between the block and a rigid ball: read, and refused with an interface.
TEST(ParseCase, ASurfacePairIsReadAndTakesNoInterface) {
  std::string text = good;
  text.replace(text.find("radius = 0.3 }"), 14, "radius = 0.3 }\nrigid = true");
  text.replace(text.find("[output]"), 8,
               "[[contact]]\nbodies = [\"block\", \"ball\"]\nfriction = 0.4\nlaw = \"surface\"\n"
               "[output]");
  const Case c = test::case_from(text);
  ASSERT_EQ(c.contact.pairs.size(), 1u);
  EXPECT_TRUE(c.contact.pairs[0].surface);
  text.replace(text.find("[output]"), 8,
               "[[interface]]\nbodies = [\"ball\", \"block\"]\n"
               "friction = { initial = 0.5, residual = 0.5, slip = 1 }\n"
               "cohesion = { initial = 0, residual = 0, slip = 1 }\n[output]");
  try {
    test::case_from(text);
    FAIL() << "an interface on a surface pair was accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("interface[0].bodies: the pair 'ball'-'block' meets at "
                                         "surface points"),
              std::string::npos)
        << e.what();
  }
}

struct BadCase {
  std::string name;
  std::string from; // text in the good case to replace
  std::string to;
  std::string message; // expected in what()
};

class BadCaseTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadCaseTest, NamesTheFileTheLineAndTheKey) {
  const BadCase& b = GetParam();
  std::string text = good;
  const auto at = text.find(b.from);
  ASSERT_NE(at, std::string::npos) << b.from;
  text.replace(at, b.from.size(), b.to);
  try {
    test::case_from(text);
    FAIL() << "no error for " << b.name;
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find(b.message), std::string::npos)
        << "got: " << e.what() << "\nexpected: " << b.message;
    EXPECT_NE(std::string(e.what()).find("inline.toml"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Errors, BadCaseTest,
    ::testing::Values(
        BadCase{
            "misspelt_key", "end_time = 1.0", "end_tme = 1.0",
            "inline.toml:2: simulation.end_time: required key is missing (line 4 has 'end_tme')"},
        BadCase{"missing_key", "end_time = 1.0\n", "",
                "simulation.end_time: required key is missing"},
        BadCase{"wrong_type", "cell_size = 0.25", "cell_size = \"fine\"",
                "inline.toml:11: grid.cell_size: expected a number, got a string"},
        BadCase{"negative_modulus", "youngs_modulus = 1e7", "youngs_modulus = -1e7",
                "inline.toml:19: material[0].youngs_modulus: must be >= 1 Pa"},
        BadCase{"poisson_half", "poisson_ratio = 0.25", "poisson_ratio = 0.5",
                "material[0].poisson_ratio: must be in [0, 0.5)"},
        BadCase{"volume_limit_below_one", "poisson_ratio = 0.25",
                "poisson_ratio = 0.25\nmax_volume_ratio = 0.9",
                "inline.toml:21: material[0].max_volume_ratio: must be > 1"},
        BadCase{"volume_limit_elastic", "poisson_ratio = 0.25",
                "poisson_ratio = 0.25\nmax_volume_ratio = 1.5",
                "inline.toml:21: material[0].max_volume_ratio: only for the plastic models"},
        BadCase{"orphan_fraction_range", "[output]",
                "[[contact]]\nfriction = 0.2\norphan_fraction = 0.6\n[output]",
                "inline.toml:40: contact[0].orphan_fraction: must be in [0, 0.5)"},
        BadCase{"normal_smoothing_range", "[output]",
                "[[contact]]\nfriction = 0.2\nnormal_smoothing = 4\n[output]",
                "inline.toml:40: contact[0].normal_smoothing: must be in [0, 3], got 4"},
        BadCase{"normal_smoothing_not_an_integer", "[output]",
                "[[contact]]\nfriction = 0.2\nnormal_smoothing = 1.5\n[output]",
                "inline.toml:40: contact[0].normal_smoothing: expected an integer"},
        BadCase{"node_law_unknown", "[output]",
                "[[contact]]\nfriction = 0.2\nnode_law = \"master\"\n[output]",
                "inline.toml:40: contact[0].node_law"},
        BadCase{"surface_law_unknown", "[output]",
                "[[contact]]\nbodies = [\"block\", \"ball\"]\nfriction = 0.2\nlaw = \"points\"\n"
                "[output]",
                "contact[0].law: 'points' is not one of: nodes, surface"},
        BadCase{"surface_law_two_deformable", "[output]",
                "[[contact]]\nbodies = [\"block\", \"ball\"]\nfriction = 0.2\nlaw = \"surface\"\n"
                "[output]",
                "contact[0].law: \"surface\" needs one rigid and one deformable body; 'block' and "
                "'ball' are both deformable"},
        BadCase{"orphan_fraction_on_a_pair", "[output]",
                "[[contact]]\nbodies = [\"block\", \"ball\"]\nfriction = 0.2\n"
                "orphan_fraction = 0.2\n[output]",
                "contact[0].orphan_fraction"},
        BadCase{"zero_density", "density = 2000", "density = 0",
                "inline.toml:18: material[0].density: must be > 0 kg/m^3"},
        BadCase{"unknown_material", "material = \"rock\"\nbox", "material = \"rok\"\nbox",
                "body[0].material: no material is named 'rok' (did you mean 'rock'?)"},
        BadCase{"outside_grid", "max = [1, 0.5]", "max = [1, 2.5]",
                "body[0].box: the body reaches outside the grid along y"},
        BadCase{"bad_scheme", "scheme = \"usl\"", "scheme = \"usll\"",
                "simulation.scheme: 'usll' is not one of: usf, usl, musl (did you mean 'usl'?)"},
        BadCase{"bad_face", "y_min = \"fixed\"", "y_min = \"fix\"",
                "grid.boundary.y_min: 'fix' is not one of: free, fixed, slip"},
        BadCase{"vector_length", "gravity = [0, -9.81]", "gravity = [0, -9.81, 0]",
                "simulation.gravity: expected an array of 2 numbers"},
        BadCase{"dimension", "dimension = 2", "dimension = 4",
                "simulation.dimension: must be in [2, 3], got 4"},
        BadCase{"flip_range", "flip = 0.95", "flip = 1.5", "simulation.flip: must be in [0, 1]"},
        BadCase{"apic_with_flip", "flip = 0.95", "flip = 0.95\napic = true",
                "simulation.flip: has no meaning under apic"},
        BadCase{"apic_with_xpic", "flip = 0.95", "xpic = 2\napic = true",
                "simulation.apic: cannot go with xpic"},
        BadCase{
            "two_geometries", "box = { min = [0, 0], max = [1, 0.5] }",
            "box = { min = [0, 0], max = [1, 0.5] }\ndisk = { center = [0.5, 0.5], radius = 0.1 }",
            "a body needs exactly one geometry"},
        BadCase{"syntax", "[output]", "[output", "inline.toml:38:"},
        BadCase{"duplicate_body", "name = \"ball\"", "name = \"block\"",
                "body[1].name: two bodies have this name"},
        BadCase{"empty_boundary", "velocity_x = 0.0", "",
                "boundary[0].velocity: a boundary must set velocity"},
        BadCase{"probe_body", "body = \"block\"\nnear", "body = \"blok\"\nnear",
                "probe[0].body: no body is named 'blok'"},
        BadCase{"ppc_range", "particles_per_cell = 2", "particles_per_cell = 0",
                "body[0].particles_per_cell: must be in [1, 8], got 0"},
        BadCase{"nan", "end_time = 1.0", "end_time = nan",
                "simulation.end_time: must be a finite number"},
        BadCase{"missing_polygon_file", "box = { min = [0, 0], max = [1, 0.5] }",
                "polygon = \"no_such.csv\"", "no_such.csv: no such file"},
        BadCase{"unknown_section", "[output]", "[outptu]",
                "outptu: unknown key (did you mean 'output'?)"},
        BadCase{"run_set_not_strings", "[output]", "[[run]]\nset = [1]\n[output]",
                "run[0].set: element 0 is not a string"},
        BadCase{"run_unknown_key", "[output]", "[[run]]\nsets = []\n[output]",
                "run[0].sets: unknown key (did you mean 'set'?)"},
        BadCase{"run_bad_override", "[output]", "[[run]]\nset = ['grid.cell_size']\n[output]",
                "inline.toml: [[run]] set (line 39) 'grid.cell_size': expected key.path=value"},
        BadCase{"run_set_no_entry", "[output]",
                "[[run]]\nset = ['simulation.end_time=2', 'body.nosuch.density=1']\n[output]",
                "[[run]] set (line 39) body.nosuch.density: no entry 'body.nosuch'"},
        BadCase{"run_set_bad_value", "[output]",
                "[[run]]\nset = [\n  'grid.cell_size=\"x\"',\n]\n[output]",
                "inline.toml: (from [[run]] set (line 40)) grid.cell_size: expected a number"},
        BadCase{"run_set_bad_word", "[output]",
                "[[run]]\nset = ['simulation.scheme=usx']\n[output]",
                "(from [[run]] set (line 39)) simulation.scheme: 'usx' is not one of"}),
    [](const auto& info) { return info.param.name; });

} // namespace
} // namespace talus
