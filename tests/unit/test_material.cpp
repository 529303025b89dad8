// Unit tests of the material library (ncf_material.h) against the paper's Tables 1 and 3.

#include "ncf_material.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

using namespace NCF;
using ::testing::HasSubstr;

static MaterialLibrary paper_materials()
{
  return MaterialLibrary::read(std::string(NCF_SOURCE_DIR) + "/potentials/ncf.materials");
}

TEST(Material, FileHasUnitsAndThePapersMaterials)
{
  auto lib = paper_materials();
  EXPECT_EQ(lib.units(), "si");
  for (auto name : {"SGL_Sigrafil_CT24-4.8/240", "SGL_Sigrafil_CT50-4.4/255", "PES_7.6tex", "PES_5.0tex"})
    EXPECT_TRUE(lib.has(name)) << name;
}

TEST(Material, CT24ChainAt69umAndHalfPacking)
{
  auto c = filament_chain(paper_materials().get("SGL_Sigrafil_CT24-4.8/240"), 69e-6, 0.5);
  EXPECT_NEAR(c.filaments, 48.6, 0.05);    // "about 49 filaments"
  EXPECT_NEAR(c.modulus, 120e9, 1.0);      // Table 3
  EXPECT_NEAR(c.density, 905.0, 1e-9);     // Table 3: 0.905 g/cm^3
  EXPECT_NEAR(c.area, M_PI * 0.25 * 69e-6 * 69e-6, 1e-20);
  EXPECT_NEAR(c.ea, 120e9 * c.area, 1e-6);
  EXPECT_NEAR(c.ea, 448.7, 0.1);
  // mass per length equals n_f filaments of the bulk fibre
  const double filament = 1810.0 * M_PI * 0.25 * 7e-6 * 7e-6;
  EXPECT_NEAR(c.mass_per_length, c.filaments * filament, 1e-15);
}

TEST(Material, CT50ChainMatchesTable3)
{
  auto c = filament_chain(paper_materials().get("SGL_Sigrafil_CT50-4.4/255"), 69e-6, 0.5);
  EXPECT_NEAR(c.modulus, 127.5e9, 1.0);
  EXPECT_NEAR(c.density, 890.0, 1e-9);
}

TEST(Material, StitchYarnDiametersFromLinearDensity)
{
  auto lib = paper_materials();
  auto y76 = yarn_chain(lib.get("PES_7.6tex"));
  auto y50 = yarn_chain(lib.get("PES_5.0tex"));
  EXPECT_NEAR(y76.diameter, 88e-6, 0.5e-6);    // Table 3: 88 um
  EXPECT_NEAR(y50.diameter, 71e-6, 0.5e-6);    // Table 3: 71 um
  EXPECT_NEAR(y76.modulus, 1.81e9, 0.005e9);
  EXPECT_NEAR(y76.density, 1250.0, 2.0);
  // one chain carries the whole yarn
  EXPECT_NEAR(y76.mass_per_length, 7.6e-6, 1e-12);
}

TEST(Material, WrongKindIsRefused)
{
  auto lib = paper_materials();
  EXPECT_THROW(filament_chain(lib.get("PES_7.6tex"), 69e-6, 0.5), InputError);
  EXPECT_THROW(yarn_chain(lib.get("SGL_Sigrafil_CT24-4.8/240")), InputError);
  EXPECT_THROW(filament_chain(lib.get("SGL_Sigrafil_CT24-4.8/240"), 69e-6, 1.5), InputError);
  EXPECT_THROW(filament_chain(lib.get("SGL_Sigrafil_CT24-4.8/240"), -1.0, 0.5), InputError);
}

struct BadFile {
  const char *text;
  const char *message;
};

class MaterialErrors : public ::testing::TestWithParam<BadFile> {};

TEST_P(MaterialErrors, NameFileLineAndProblem)
{
  try {
    MaterialLibrary::parse(GetParam().text, "bad.materials");
    FAIL() << "no error for: " << GetParam().text;
  } catch (const InputError &e) {
    EXPECT_THAT(e.what(), HasSubstr(GetParam().message));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, MaterialErrors,
    ::testing::Values(
        BadFile{"filament a modulus 1 density 1 filament_diameter 1\n", "bad.materials:1: the first line must be 'UNITS: si'"},
        BadFile{"UNITS: metal\n", "bad.materials:1: units 'metal' are not supported"},
        BadFile{"", "has no 'UNITS: si' line"},
        BadFile{"UNITS: si\nfibre a modulus 1\n", "bad.materials:2: unknown record 'fibre'"},
        BadFile{"UNITS: si\nfilament\n", "bad.materials:2: record 'filament' has no material name"},
        BadFile{"UNITS: si\nfilament a modulus\n", "bad.materials:2: keyword 'modulus' has no value"},
        BadFile{"UNITS: si\nfilament a modulus -3 density 1 filament_diameter 1\n", "value '-3' of 'modulus' must be > 0"},
        BadFile{"UNITS: si\nfilament a modulus 1x density 1 filament_diameter 1\n", "value '1x' of 'modulus' is not a number"},
        BadFile{"UNITS: si\nfilament a modulus 1 density 1 color 3\n", "unknown keyword 'color' for material 'a'"},
        BadFile{"UNITS: si\nfilament a modulus 1 density 1\n", "filament material 'a' needs 'filament_diameter'"},
        BadFile{"UNITS: si\nyarn b modulus 1 density 1\n", "yarn material 'b' needs 'linear_density'"},
        BadFile{"UNITS: si\nyarn b modulus 1 density 1 linear_density 1\nyarn b modulus 1 density 1 linear_density 1\n",
                "bad.materials:3: material 'b' is defined twice (first on line 2)"}));

TEST(Material, UnknownMaterialListsTheKnownOnes)
{
  try {
    paper_materials().get("T700");
    FAIL();
  } catch (const InputError &e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown material 'T700'"));
    EXPECT_THAT(e.what(), HasSubstr("PES_5.0tex"));
  }
}
