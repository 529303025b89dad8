// dump image of the tools (Fix::image of fix ncf/plate and fix ncf/needles): the shapes LAMMPS
// draws from the codes the fixes return. The codes are numbered differently in LAMMPS 4 Feb 2025
// (dump_image.cpp) and 4 Jul 2026 (graphics.h); with the wrong ones the plates are drawn as huge
// cylinders (or the dump hangs) and the needles as spheres. Only the fix is drawn (an empty atom
// group, no box), on a black background, into a PPM file that the test reads back.

#include "ncf_lammps_test.h"

#include "fmt/format.h"
#include "lammps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <string>
#include <vector>

using namespace ncftest;

namespace {

// a straight chain of n nodes along x at y = 5e-4, z = z0 (two atom types: 2 only colours tools)
std::string write_line(const std::string &dir, int n, double a, double z0)
{
  const std::string path = dir + "/line.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "line\n\n%d atoms\n2 atom types\n%d bonds\n1 bond types\n\n", n, n - 1);
  fprintf(fp, "0 %.17g xlo xhi\n0 1e-3 ylo yhi\n-1e-3 2e-3 zlo zhi\n\n", (n + 1) * a);
  fprintf(fp, "Masses\n\n1 1e-9\n2 1e-9\n\nAtoms # bond\n\n");
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g 5e-4 %.17g\n", i + 1, (i + 1) * a, z0);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < n; i++) fprintf(fp, "%d 1 %d %d\n", i, i, i + 1);
  fclose(fp);
  return path;
}

void load(Lammps &l, const std::string &data)
{
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary p p f
comm_modify cutoff 6e-4
bond_style ncf/chain
)");
  l.cmd("read_data " + data);
  l.cmds(R"(
bond_coeff 1 ea 100
group nothing empty
)");
}

// the pixels of a binary PPM (P6) that are not black: their count and bounding box
struct Drawn {
  int width = 0, height = 0, count = 0;
  int xmin = 1 << 30, xmax = -1, ymin = 1 << 30, ymax = -1;
};

// the next number of a PPM header, skipping white space and comments (LAMMPS 4 Jul 2026 writes a
// "# CREATOR" line, 4 Feb 2025 none); -1 if there is none
int ppm_header_number(FILE *fp)
{
  int c = fgetc(fp);
  while (c == '#' || std::isspace(c)) {
    if (c == '#')
      while (c != '\n' && c != EOF) c = fgetc(fp);
    c = fgetc(fp);
  }
  if (!std::isdigit(c)) return -1;
  int v = 0;
  while (std::isdigit(c)) {
    v = 10 * v + (c - '0');
    c = fgetc(fp);
  }
  return v;    // the one white-space character after the number is consumed
}

Drawn read_ppm(const std::string &path)
{
  Drawn d;
  FILE *fp = fopen(path.c_str(), "rb");
  if (!fp) return d;
  const bool p6 = fgetc(fp) == 'P' && fgetc(fp) == '6';
  d.width = p6 ? ppm_header_number(fp) : -1;
  d.height = p6 ? ppm_header_number(fp) : -1;
  const int maxval = p6 ? ppm_header_number(fp) : -1;
  if (d.width <= 0 || d.height <= 0 || maxval != 255) {
    fclose(fp);
    d.width = d.height = 0;
    return d;
  }
  std::vector<unsigned char> px(3 * (size_t) d.width * d.height);
  const size_t got = fread(px.data(), 1, px.size(), fp);
  fclose(fp);
  if (got != px.size()) {
    d.width = d.height = 0;
    return d;
  }
  for (int y = 0; y < d.height; y++)
    for (int x = 0; x < d.width; x++) {
      const unsigned char *p = &px[3 * ((size_t) y * d.width + x)];
      if (p[0] + p[1] + p[2] < 30) continue;
      d.count++;
      d.xmin = std::min(d.xmin, x);
      d.xmax = std::max(d.xmax, x);
      d.ymin = std::min(d.ymin, y);
      d.ymax = std::max(d.ymax, y);
    }
  return d;
}

// one picture of the tools only (group nothing) at step 0, as the image file `name`.0.ppm
Drawn draw_once(Lammps &l, const std::string &dir, const std::string &name, const std::string &view,
                const std::string &fix, const std::string &colour)
{
  l.cmd(fmt::format("dump img nothing image 1 {}/{}.*.ppm type type {} size 200 200 box no 0 {}",
                    dir, name, view, fix));
  l.cmd("dump_modify img acolor * " + colour + " backcolor black");
  l.cmd("run 0");
  return read_ppm(dir + "/" + name + ".0.ppm");
}

}    // namespace

TEST(DumpImage, PlateIsDrawnAsAFilledRectangle)
{
  // the moving upper plate seen from above, filled triangles only (fix flag 1): it covers the box
  auto dir = scratch_dir("dump_image_plate");
  Lammps l;
  load(l, write_line(dir, 4, 2e-4, 3e-4));
  l.cmd("fix plate all ncf/plate kn 2e7 diameter 1 69e-6 lower z 0.0 upper target 1e-3 1e-3 1.0");
  const Drawn d = draw_once(l, dir, "plate", "view 0 0 up 0 1 0 zoom 1.5", "fix plate type 1 0", "red");
  ASSERT_EQ(d.width, 200) << "no readable plate.0.ppm";
  // the plate covers the box's 1 mm x 1 mm (about 50 x 50 pixels at this zoom, the view being
  // scaled to the box's 3 mm height): a filled square, not the outline or cylinders of other codes
  const double share = (double) d.count / (d.width * d.height);
  EXPECT_GT(share, 0.03) << "the plate covers " << share << " of the image";
  const double fill = (double) d.count / ((d.xmax - d.xmin + 1.0) * (d.ymax - d.ymin + 1.0));
  EXPECT_GT(fill, 0.9) << "the drawn pixels fill " << fill << " of their bounding box";
  const double aspect = (d.xmax - d.xmin + 1.0) / (d.ymax - d.ymin + 1.0);
  EXPECT_NEAR(aspect, 1.0, 0.1) << "the square plate is drawn " << aspect << " times as wide as tall";
}

TEST(DumpImage, NeedleIsDrawnAsALongCylinder)
{
  // a needle 1.5 mm long (clear of the chain) drawn 0.1 mm thick (fix flag 1e-4), seen from the
  // side: a tall bar
  auto dir = scratch_dir("dump_image_needle");
  Lammps l;
  load(l, write_line(dir, 4, 2e-4, 0.0));
  l.cmd("fix nd all ncf/needles diameter 0.5e-3 kn 1e8 chain 1 69e-6 at 5e-4 9e-4 move -5e-4 0 "
        "length 1.5e-3");
  const Drawn d = draw_once(l, dir, "needle", "view 90 0 zoom 1.5", "fix nd type 1e-4 0", "green");
  ASSERT_EQ(d.width, 200) << "no readable needle.0.ppm";
  ASSERT_GT(d.count, 0) << "nothing drawn";
  const double tall = (d.ymax - d.ymin + 1.0) / (d.xmax - d.xmin + 1.0);
  EXPECT_GT(tall, 5.0) << "the needle's picture is " << tall << " times as tall as wide";
}
