/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   The error the engine-free readers throw for bad user input (a materials file, a card, a
   constraint set-up): its message names the file, line or keyword and the problem. The LAMMPS
   styles turn it into error->all; the tools print it and exit. No LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_INPUT_ERROR_H
#define NCF_INPUT_ERROR_H

#include <stdexcept>

namespace NCF {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}    // namespace NCF

#endif
