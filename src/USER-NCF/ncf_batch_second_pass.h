/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   The gathering step of the second pass of the batched kernels (segment_contact_batch,
   node_contact_batch): the lanes a first, cheaper pass flagged (status -2 or below) are copied into a
   compacted batch, which the kernel computes again with its full version and whose results it
   puts back. Internal to ncf_contact_batch.cpp and ncf_cap_batch.cpp; no LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_BATCH_SECOND_PASS_H
#define NCF_BATCH_SECOND_PASS_H

namespace NCF {

// Batch: a batch type with n, status[N], x[NX][N], dc[N], kn[N], ramp[N] (N lanes). The inputs
// and statuses of the lanes of b with status -2 or below copied into m (m.n of them, in order); lane[j]: the lane of b
// that lane j of m came from. Returns m.n. Always inlined, so that every version of the calling
// kernel (target_clones) compiles it for its own instruction set.
template <int NX, class Batch>
inline __attribute__((always_inline)) int gather_flagged_lanes(const Batch &b, Batch &m, int *lane)
{
  m.n = 0;
  for (int l = 0; l < b.n; l++) {
    lane[m.n] = l;
    m.n += b.status[l] <= -2.0;
  }
  for (int j = 0; j < m.n; j++) {
    const int l = lane[j];
    for (int k = 0; k < NX; k++) m.x[k][j] = b.x[k][l];
    m.dc[j] = b.dc[l];
    m.kn[j] = b.kn[l];
    m.ramp[j] = b.ramp[l];
    m.status[j] = b.status[l];
  }
  return m.n;
}

}    // namespace NCF

#endif
