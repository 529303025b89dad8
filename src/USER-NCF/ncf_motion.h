/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free prescribed motion of a rigid tool along z (plates, needles): fixed, constant
   speed, or to a target at a speed; a variable-driven motion is evaluated by the caller.
------------------------------------------------------------------------- */

#ifndef NCF_MOTION_H
#define NCF_MOTION_H

#include <cmath>

namespace NCF {

struct Motion {
  enum Kind { NONE = 0, FIXED = 1, MOVE = 2, TARGET = 3, VARIABLE = 4 };
  int kind = NONE;
  double z0 = 0.0;         // start (FIXED: the position)
  double ztarget = 0.0;    // TARGET: where it stops
  double speed = 0.0;      // MOVE: signed speed; TARGET: speed > 0

  // position and velocity a time t after the start (not for VARIABLE)
  void at(double t, double &z, double &v) const
  {
    z = z0;
    v = 0.0;
    if (kind == MOVE) {
      z = z0 + speed * t;
      v = speed;
    } else if (kind == TARGET) {
      const double dist = std::fabs(ztarget - z0), dir = ztarget >= z0 ? 1.0 : -1.0;
      if (speed * t >= dist) {
        z = ztarget;
      } else {
        z = z0 + dir * speed * t;
        v = dir * speed;
      }
    }
  }

  bool same_as(const Motion &o) const
  {
    return kind == o.kind && z0 == o.z0 && ztarget == o.ztarget && speed == o.speed;
  }

  // 4 numbers for restart files
  void pack(double *buf) const
  {
    buf[0] = kind;
    buf[1] = z0;
    buf[2] = ztarget;
    buf[3] = speed;
  }
  void unpack(const double *buf)
  {
    kind = (int) buf[0];
    z0 = buf[1];
    ztarget = buf[2];
    speed = buf[3];
  }
};

}    // namespace NCF

#endif
