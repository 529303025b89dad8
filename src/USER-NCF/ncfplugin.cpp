/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Plugin registration: every style of the package, from the generated list ncf_styles.h
   (cmake/NCFStyles.cmake reads the XxxStyle() macros of the headers).
------------------------------------------------------------------------- */

#include "comm.h"
#include "lammps.h"
#include "lammpsplugin.h"
#include "utils.h"
#include "version.h"

#include "ncf_styles.h"
#include "ncf_version.h"

using namespace LAMMPS_NS;

namespace {

// pair and bond styles and commands are built from the LAMMPS instance alone, fixes and
// computes also get their arguments
template <class T> void *create_plain(void *lmp)
{
  return new T(static_cast<LAMMPS *>(lmp));
}
template <class T> void *create_with_args(void *lmp, int narg, char **arg)
{
  return new T(static_cast<LAMMPS *>(lmp), narg, arg);
}

const char INFO[] = "USER-NCF " NCF_VERSION " (git " NCF_GIT_REVISION
                    "): digital-chain virtual manufacturing of non-crimp fabrics";

[[maybe_unused]] void set_creator(lammpsplugin_t &p, void *(*f)(void *) )
{
  p.creator.v1 = (lammpsplugin_factory1 *) f;
}
[[maybe_unused]] void set_creator(lammpsplugin_t &p, void *(*f)(void *, int, char **) )
{
  p.creator.v2 = (lammpsplugin_factory2 *) f;
}

}    // namespace

#define NCF_CREATOR_bond(Class) &create_plain<Class>
#define NCF_CREATOR_pair(Class) &create_plain<Class>
#define NCF_CREATOR_fix(Class) &create_with_args<Class>
#define NCF_CREATOR_compute(Class) &create_with_args<Class>
#define NCF_CREATOR_command(Class) &create_plain<Class>

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  auto register_plugin = (lammpsplugin_regfunc) regfunc;
  lammpsplugin_t plugin;
  plugin.version = LAMMPS_VERSION;
  plugin.info = INFO;
  plugin.author = "USER-NCF developers";
  plugin.handle = handle;

#define NCF_REGISTER(KIND, NAME, CLASS)           \
  plugin.style = #KIND;                           \
  plugin.name = NAME;                             \
  set_creator(plugin, NCF_CREATOR_##KIND(CLASS)); \
  (*register_plugin)(&plugin, lmp);

  NCF_FOR_EACH_STYLE(NCF_REGISTER)
#undef NCF_REGISTER

  // LAMMPS prints the info string only for some ways of loading; the version and revision belong
  // in every log, so that a result can be traced to the code that made it
  auto *instance = static_cast<LAMMPS *>(lmp);
  if (instance->comm->me == 0) utils::logmesg(instance, "{}\n", INFO);
}
