/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   pair_style ncf/contact: cylinder-cylinder (segment-segment) contact between chain segments,
   penalty normal force and Coulomb friction with a per-contact slip history. Contact law in
   ncf_contact.h (engine-free); see doc/pair_ncf_contact.md.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(ncf/contact,PairNCFContact);
// clang-format on
#else

#ifndef LMP_PAIR_NCF_CONTACT_H
#define LMP_PAIR_NCF_CONTACT_H

#include "pair.h"

#include "fix_ncf_contact_history.h"

#include "ncf_box_grid.h"
#include "ncf_contact.h"
#include "ncf_contact_model.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class PairNCFContact : public Pair, public NCFContactHistoryOwner {
 public:
  // IDs of the fix property/atom stores created by the style
  static constexpr const char *TOPO_ID = "NCF_CONTACT_TOPO";    // chain neighbours (ghost yes)
  static constexpr const char *FORCE_ID = "NCF_CONTACT_F";      // per-atom |contact force|
  static constexpr const char *WORK_ID = "NCF_CONTACT_WORK";    // per-atom work estimate
  // the work estimate d_ncf_work of a node (keyword work), in units of a node without contacts
  // (its bonds, integration and ghost copies): 1 + WORK_NEAR per pair list entry in reach at the
  // build (it goes through the law) + WORK_FAR per other entry (bound tests only) + WORK_CAP per
  // node cap (instruction counts on the compacted bench mat, doc/pair_ncf_contact.md)
  static constexpr double WORK_NEAR = 3.3;
  static constexpr double WORK_FAR = 0.27;
  static constexpr double WORK_CAP = 0.2;
  // the fix property/atom that held the friction history in restart files of earlier versions
  static constexpr const char *OLD_HIST_ID = "NCF_CONTACT_HIST";

  PairNCFContact(class LAMMPS *);
  ~PairNCFContact() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void *extract(const char *, int &) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  // longest segment the neighbour and ghost cutoffs were sized for (after init)
  double max_segment_length() const { return lmax_used; }
  bool friction_active() const override { return use_history; }
  // write the friction history of the last step into the per-atom store (fix
  // ncf/contact/history calls it before atoms migrate and at the end of a run)
  void sync_history() override;
  double critical_timestep() const { return dt_critical; }

 protected:
  // settings
  double ramp_frac;      // ramp half-width as a fraction of the contact distance
  double core;           // stiffness factor of the core (NCF::ContactOptions::core)
  double endcap_frac;    // extension of segments at free chain ends, fraction of the diameter
  double lmax_user;      // longest segment given by the user (0 = from the data at init)
  int maxcontacts;       // history slots per node at the start (the store grows beyond)
  int fatom_every;       // per-node contact force magnitude every N steps (0: none)
  int work_flag;         // 1: the per-node work estimate d_ncf_work, set at every list build
  int dtcheck;           // 2 error, 1 warn, 0 no check of the time step against dt_critical
  int oneway;            // 1: the one-way law (segment A = lower key against B; caps at full
                         // weight), 0: the symmetric law (NCF::chain_contact; default)
  double dt_critical;    // critical time step of the contacts (estimated at init)
  // the communication cutoff as the user gave it (comm_modify cutoff; -1: not known yet) and as
  // this style last set it (the user's raised to what the style needs)
  double ghost_user, ghost_set;

  // the contact coefficients per type pair and the diameter per type (index 0 unused)
  NCF::ContactTable table;
  double **cut, **reachf;    // per type pair: cutoff and reach D (1 + ramp)

  // derived at init
  double lmax_used;
  bool lmax_warned = false;    // the warning for another bond style given once
  std::string lmax_note() const;
  double reach_max;     // largest D (1 + ramp) over the type pairs (without end caps)
  double diam_max;      // largest diameter (of a type)
  bool use_history;     // any mu > 0: history stored and communicated
  bool use_velocity;    // friction or damping: ghost velocities needed
  int idx_cnb, idx_fc, idx_work;
  class FixNCFContactHistory *fhist;    // the per-atom store of the friction history (mu > 0)
  int comm_sized;    // the comm_forward that LAMMPS sized its buffers for (at init)
  enum { COMM_HIST, COMM_FORCE, COMM_NEED };
  int comm_mode;    // what forward/reverse communication carries: history rows, contact forces,
                    // the flags of the rows that take-overs may read (hneed)
  // per local+ghost atom: 1 if a take-over of this rank or another may read its history row
  // (the rows of owned nodes so flagged and of their ghost copies are the only ones the history
  // communication carries); valid while hneed_valid, set by exchange_row_needs
  std::vector<double> hneed;
  bool hneed_valid;

  // per-step work arrays
  std::vector<double> endext;    // per local+ghost atom: extension at a free chain end [m]
  std::vector<int> segp;         // per local+ghost atom, 2 slots: partner index of owned segments
  std::vector<int> nbr;          // per local+ghost atom, 2 slots: chain neighbours (-1, -2 missing)
  // friction history per entry of the pair list between two list builds (loaded from the
  // per-atom store at the build), in two buffers: the last step's (hlast) and this step's; the
  // per-atom store is written from it when LAMMPS needs it (sync_history)
  std::vector<double> pslip[2];          // per pair list entry: slip vector
  std::vector<unsigned char> phas[2];    // per pair list entry: 1 if in contact (slip kept)
  int hlast;                             // buffer of the last step
  bool rows_current;                     // the per-atom rows hold buffer hlast
  std::vector<int> pfirst;               // per owned node: first pair list entry it owns
  std::vector<int> deferred;      // pair list entries whose take-over waits for ghost history
  std::vector<int> work;          // pair list entries gathered for a loop (compute, store)
  NCF::ContactBatch batch;        // lanes of the batched contact law
  NCF::TangentialBatch tbatch;    // lanes of the batched dashpot and friction
  NCF::CapBatch cbatch;           // lanes of the batched node caps
  std::vector<double> fcon;       // per local+ghost atom contact force (3), for fatom
  std::vector<double> xd;         // per local+ghost atom, one cache line: position, displacement
                                  // bound, velocity, end-cap extension (this step)
  std::vector<double> dmn;        // per local+ghost atom: the displacement bound again (dense)
  double keep_last;    // fraction of the pair entries near by the global bound kept by their own
                       // nodes' bounds in the last step

  // candidate lists (atom indices), rebuilt when LAMMPS reneighbours
  struct PairCand {
    int a0, a1, b0, b1;    // segment A = a0-a1 (a0 owned, lower tag), B = b0-b1; key(A) < key(B)
    unsigned tp : 31;      // type pair (index into tpar)
    unsigned ext : 1;      // 1 if a node of A or B is a free chain end (segment extended)
    float reach;    // the law is zero while the displacement bound of a node of A plus that of a
                    // node of B (the largest of each) stays below reach: gap / grow, rounded
                    // down, with gap the distance of A and B at the build (extended at free
                    // ends, B also by the ramp half-width) minus D and grow the bound of how
                    // fast it can close (gap_growth)
  };
  struct CapCand {
    int a0, a1;     // segment A (a0 owned)
    int p, n, q;    // interior node n and its chain neighbours
    int tp;         // type pair of A and the node (index into tpar)
    double gap;     // distance of segment A from node n at the build minus D, rounded down
  };
  // the coefficients of a type pair as the compute loops use them, in one small table (set at
  // init), so that a list entry needs neither the types of its nodes nor the 2d arrays
  struct TypePair {
    double dc;      // contact distance D
    double kn;      // normal stiffness per length
    double ramp;    // ramp half-width e
    double kt;      // tangential stiffness per length (ktr kn)
    double mu, damp;
  };
  std::vector<TypePair> tpar;    // index itype * tstride + jtype
  int tstride;                   // ntypes + 1 (set at init)
  int type_pair(int itype, int jtype) const { return itype * tstride + jtype; }
  std::vector<double> xbuild;    // positions of all local and ghost atoms at the build
  std::vector<PairCand> plist;
  double lseg_build;    // longest owned segment at the build
  std::vector<CapCand> clist;
  std::vector<int> ghosts_used;    // the ghosts that an entry of plist or clist refers to
  // virtual nodes: the extended ends of segments at free chain ends, which replace those ends in
  // plist (index nall_build + v): the free end and its chain neighbour; the forces on them
  std::vector<int> vreal, vnbr;
  int nall_build;
  std::vector<double> fvirt;
  std::vector<double> vgeom;    // per virtual node, this step: unit vector u (3), e / l
  // the atom index of a node of a pair list entry (the free end for a virtual node)
  int real_of(int k) const { return k < nall_build ? k : vreal[k - nall_build]; }
  bool lists_valid;
  bigint lists_ncalls;
  int lists_nlocal, lists_nall;

  // boxes (segments or nodes) binned by their centres, for the list build (ncf_box_grid.h)
  using BoxGrid = NCF::BoxGrid<tagint>;
  BoxGrid gseg, gext, gcap;    // segments, segments extended at free ends, node caps
  std::vector<int> gcand;

  void allocate();
  // the candidate lists in steps (pair_ncf_contact_list.cpp), with the bounds of one build
  struct ListBounds {
    double skin;         // LAMMPS's neighbour skin
    double slack;        // round-off slack of the bounds
    double hm;           // half of the largest reach + skin, plus the slack
    double gap_slack;    // what the gap of a list entry is rounded down by
    double hcap;         // half width of a node cap's box
  };
  void build_lists();
  ListBounds prepare_build();
  void fill_grids(const ListBounds &);
  void search_owned_segments(const ListBounds &);
  void consider_pair(const ListBounds &, int ao, int ia, int bo, int jb);
  void search_caps(const ListBounds &, int ao, int ia, const double *ca, const double *exa);
  void mark_used_ghosts();
  void make_virtual_ends();
  void load_history();
  void store_history(int, bool only_needed = false);
  void create_stores();
  void create_peratom_outputs();
  void create_history_fix();
  void attach_history_store();
  void import_old_history();
  void fill_topology();
  void find_lmax();
  void check_coincident(const std::vector<double> &xall);
  void set_segments();
  const double *find_slip_row(int m, tagint ohi, tagint blo, tagint bhi) const;
  const double *find_slip_entry(int m, tagint ohi, tagint blo, tagint bhi) const;
  bool inherit_slip(tagint a0, tagint a1, tagint b0, tagint b1, double *slip,
                    bool local_only) const;
  // the neighbouring segment pairs a new contact (a0-a1, b0-b1) may take its slip over from, in
  // the order they are tried: for each, the owner index of its history (-1: not on this rank)
  // and the keys, owner segment M and other segment O; returns how many
  struct TakeOver {
    int m;
    tagint mhi, olo, ohi;
  };
  int takeover_candidates(tagint a0, tagint a1, tagint b0, tagint b1, TakeOver *out) const;
  void exchange_row_needs();
  void other_partner(tagint node, tagint not_this, tagint &out) const;
  // compute() in named steps on the state of one step (pair_ncf_contact_compute.cpp)
  struct Step;
  void refresh_lists(const Step &);
  void load_rows(Step &);
  void check_lengths(const Step &);
  void begin_history(Step &);
  int gather_pairs(const Step &, int &nnear);
  void pairs_batched(Step &, int nwork, int nnear);
  void set_lane_coefficients(int lane, const TypePair &);
  void flush_lanes(Step &);
  void deferred_takeovers(Step &);
  void node_caps(Step &);
  void map_virtual_forces(Step &);
  void finish_outputs(Step &);
  // the contact of one pair list entry by the scalar law: prepare, law, finish (pair_contact all
  // three); true if deferred
  bool scalar_prepare(const Step &, int e, bool &had) const;
  NCF::SegmentContact scalar_law(const Step &, int e) const;
  bool scalar_finish(Step &, int e, NCF::SegmentContact, bool had, bool may_defer);
  bool pair_contact(Step &, int e, bool may_defer);
  double *start_slip(const Step &, int e, bool had, bool may_defer);
  double real_penetration(const Step &, const PairCand &) const;
  // per-atom energy and virial (and the global virial without fdotr) of one contact and of the
  // mapping of a virtual node's force onto its free end and neighbour (pair_ncf_contact_compute)
  void tally_contact(int n, const int *node, const double *const *xm, const double *fm,
                     double energy);
  void tally_virtual_end(int k, int j, double e, const double *u, const double *fv);
};

}    // namespace LAMMPS_NS

#endif
#endif
