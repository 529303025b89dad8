// pair_style ncf/contact with a chain closed on itself through a periodic box (a stitching yarn):
// its closing bond has no consistent image flags, and the segment lengths that size the candidate
// lists and the ghost shell must still be those of its elements, not a box length.

#include "ncf_lammps_test.h"

#include "comm.h"
#include "lammps.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace ncftest;

TEST(PairContactRing, ClosedChainThroughTheBoxSizesLmaxByItsElements)
{
  const std::string dir = scratch_dir("pair_contact_ring");
  const int n = 20;
  const double a = 1e-4, box = n * a;    // 20 elements of 0.1 mm closing through x
  const std::string path = dir + "/ring.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "ring\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", n, n);
  fprintf(fp, "0 %.17g xlo xhi\n0 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n", box);
  fprintf(fp, "Masses\n\n1 1e-9\n\nAtoms # bond\n\n");
  // every node in the box with image flags 0: the bond n-1 closes the ring across the x face
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g 5e-4 0 0 0 0\n", i + 1, (i + 0.5) * a);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i <= n; i++) fprintf(fp, "%d 1 %d %d\n", i, i, i % n + 1);
  fclose(fp);

  Lammps l;
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary p p f
bond_style ncf/chain
)");
  l.cmd("read_data " + path);
  l.cmds(R"(
bond_coeff 1 ea 10.0
pair_style ncf/contact
pair_coeff * * kn 1e9 diameter 5e-5
neighbor 1e-5 bin
comm_modify vel yes
timestep 1e-9
run 0
)");
  // the ghost shell the style asks for is a few lmax (each 1.1 x the longest element, 0.1 mm)
  // plus the contact reach; a box-long closing bond (2 mm) made it more than 6 mm
  const double cut = l.lmp->comm->cutghostuser;
  EXPECT_GT(cut, 2.0 * a);
  EXPECT_LT(cut, 6.0 * a) << "the closing bond across the x face was measured as a box length";
}
