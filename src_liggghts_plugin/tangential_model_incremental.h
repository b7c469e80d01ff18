// SPDX-License-Identifier: GPL-2.0-or-later
/* Tangential contact model `incremental` (docs/tangential_incremental.md):
   the tangential force of PFC's Hertz model. The contact stores the
   tangential FORCE (3 history values), turns it onto the current contact
   plane, adds -k_t v_t dt with the current k_t of the normal model (for
   `model hertz`, k_t = 8 G* sqrt(R* delta_n), the stiffness of PFC's Hertz
   model for equal grains) and caps it at mu |F_n|. `tangential history`
   stores the displacement instead, so its force follows k_t down when the
   normal force falls; this one keeps the force (PFC's default: its option
   to scale the shear force down on normal unloading is off).
   The update rule itself is in crush_tangential_kernel.h.
   Use: pair_style gran model hertz tangential incremental
        fix ID all wall/gran model hertz tangential incremental ...
   The combination with hertz, no cohesion, no rolling friction and the
   default surface is registered by cmake/PrepareLiggghtsSource.cmake. */

#ifdef TANGENTIAL_MODEL
TANGENTIAL_MODEL(TANGENTIAL_INCREMENTAL,incremental,9)
#else
#ifndef TANGENTIAL_MODEL_INCREMENTAL_H_
#define TANGENTIAL_MODEL_INCREMENTAL_H_
#include "contact_models.h"
#include "tangential_model_base.h"
#include "update.h"
#include "error.h"
#include "crush_tangential_kernel.h"

namespace LIGGGHTS {
namespace ContactModels
{
  template<>
  class TangentialModel<TANGENTIAL_INCREMENTAL> : public TangentialModelBase
  {
  public:
    TangentialModel(LAMMPS * lmp, IContactHistorySetup * hsetup, class ContactModelBase * c) :
      TangentialModelBase(lmp, hsetup, c),
      mu_(NULL),
      elastic_potential_(false),
      dissipated_energy_(false)
    {
      // The stored tangential force (N): history values "ft_x/y/z".
      force_offset_ = hsetup->add_history_value("ft_x", "1");
      hsetup->add_history_value("ft_y", "1");
      hsetup->add_history_value("ft_z", "1");
    }

    inline void registerSettings(Settings & settings)
    {
      // Accepted so that a deck that asks for them gets a clear refusal
      // (postSettings) rather than a silently missing energy term.
      settings.registerOnOff("computeElasticPotential", elastic_potential_, false);
      settings.registerOnOff("computeDissipatedEnergy", dissipated_energy_, false);
    }

    inline void postSettings(IContactHistorySetup *, ContactModelBase *)
    {
      if (elastic_potential_ || dissipated_energy_)
        error->all(FLERR, "tangential incremental: computeElasticPotential and "
                   "computeDissipatedEnergy are not available (allowed: off); "
                   "use tangential history for the energy bookkeeping of LIGGGHTS");
    }

    inline void connectToProperties(PropertyRegistry & registry)
    {
      registry.registerProperty("coeffFrict", &MODEL_PARAMS::createCoeffFrict);
      registry.connect("coeffFrict", mu_, "tangential_model incremental");
    }

    inline void surfacesIntersect(const SurfacesIntersectData & sidata, ForceData & i_forces, ForceData & j_forces)
    {
      if (sidata.contact_flags)
        *sidata.contact_flags |= CONTACT_TANGENTIAL_MODEL;

      double * const stored = &sidata.contact_history[force_offset_];
      const double n[3] = { sidata.en[0], sidata.en[1], sidata.en[2] };
      const double vt[3] = { sidata.vtr1, sidata.vtr2, sidata.vtr3 };
      const double limit = mu_[sidata.itype][sidata.jtype] * std::fabs(sidata.Fn);

      // Work on a copy; write it back only on a step that updates history
      // (not on the extra force evaluations LIGGGHTS makes without one).
      double ft[3] = { stored[0], stored[1], stored[2] };
      const bool update_history = sidata.computeflag && sidata.shearupdate;
      bool sliding;
      if (update_history) {
        sliding = CrushKernels::tangential_force_step(ft, n, vt, sidata.kt, update->dt, limit);
        stored[0] = ft[0];
        stored[1] = ft[1];
        stored[2] = ft[2];
      } else {
        sliding = CrushKernels::tangential_force_cap(ft, limit);
      }

      // A sticking contact also gets the tangential dashpot of the normal
      // model (zero when the restitution is 1, as in inputs/materials_ne34.in),
      // not stored, as with `tangential history`.
      if (!sliding) {
        ft[0] -= sidata.gammat * vt[0];
        ft[1] -= sidata.gammat * vt[1];
        ft[2] -= sidata.gammat * vt[2];
      }

      // Torque of a force at the contact point, a distance cri (crj) from the
      // centre of i (j) along -n (+n): -cri n x F_t on i, -crj n x F_t on j.
      const double nxf[3] = { n[1] * ft[2] - n[2] * ft[1],
                              n[2] * ft[0] - n[0] * ft[2],
                              n[0] * ft[1] - n[1] * ft[0] };
      if (sidata.is_wall) {
        const double a = sidata.area_ratio;
        for (int k = 0; k < 3; k++) {
          i_forces.delta_F[k] += ft[k] * a;
          i_forces.delta_torque[k] += -sidata.cri * nxf[k] * a;
        }
      } else {
        for (int k = 0; k < 3; k++) {
          i_forces.delta_F[k] += ft[k];
          j_forces.delta_F[k] -= ft[k];
          i_forces.delta_torque[k] += -sidata.cri * nxf[k];
          j_forces.delta_torque[k] += -sidata.crj * nxf[k];
        }
      }
    }

    inline void surfacesClose(SurfacesCloseData & scdata, ForceData &, ForceData &)
    {
      // The contact opened: it starts again from zero force.
      if (scdata.contact_flags)
        *scdata.contact_flags &= ~CONTACT_TANGENTIAL_MODEL;
      if (!scdata.contact_history)
        return;
      double * const stored = &scdata.contact_history[force_offset_];
      stored[0] = stored[1] = stored[2] = 0.0;
    }

    inline void beginPass(SurfacesIntersectData &, ForceData &, ForceData &) {}
    inline void endPass(SurfacesIntersectData &, ForceData &, ForceData &) {}

  private:
    double ** mu_;
    int force_offset_;
    bool elastic_potential_;
    bool dissipated_energy_;
  };
}
}
#endif // TANGENTIAL_MODEL_INCREMENTAL_H_
#endif
