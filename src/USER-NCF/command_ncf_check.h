/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   ncf/check: the input checks of the stage scripts (examples/manufacturing): a -var's type and
   range, a required variable, a file, the generator's settings, the stage and fabric of a restart
   file, and the mark that stage_end.lmp puts into every restart file; each failure stops with
   error->all naming the script, the variable and the value. See doc/ncf_check.md.
------------------------------------------------------------------------- */

#ifdef COMMAND_CLASS
// clang-format off
CommandStyle(ncf/check,NCFCheck);
// clang-format on
#else

#ifndef LMP_COMMAND_NCF_CHECK_H
#define LMP_COMMAND_NCF_CHECK_H

#include "command.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class NCFCheck : public Command {
 public:
  NCFCheck(class LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override;

  // the prefixes of the two marker groups a stage's restart file carries
  static constexpr const char *STAGE_GROUP = "ncf_stage_";
  static constexpr const char *FABRIC_GROUP = "ncf_fabric_";

 private:
  std::string script;
  void check_var(const std::vector<std::string> &);
  void check_required(const std::vector<std::string> &);
  void check_file(const std::vector<std::string> &);
  void check_folder(const std::vector<std::string> &);
  void check_settings(const std::vector<std::string> &);
  void check_restart(const std::vector<std::string> &);
  void check_needles(const std::vector<std::string> &);
  void mark(const std::vector<std::string> &);
  // the variables a settings file defines (names), and the value of ncf_fabric ("" if none)
  bool read_settings(const std::string &file, std::vector<std::string> &names, std::string &fabric);
  // the suffix of the first group named PREFIX*, "" when there is none
  std::string marker(const char *prefix);
};

}    // namespace LAMMPS_NS

#endif
#endif
