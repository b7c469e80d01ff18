// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   The one loop over the particles near the granular walls, for the two
   places that look at wall contacts themselves:
   - FixCrushParticle::find_candidates_walls (the per-step breakage scan,
     which also wants the gap of particles near a wall but not touching it);
   - CrushEnergy::wall_hits (elastic energy of wall contacts).

   Not a kernel: it walks LIGGGHTS' wall neighbour lists. For every owned
   particle i listed near a wall (a mesh triangle, or a primitive wall whose
   group holds i) for which keep(i) is true, it calls
       visit(i, wall, mesh, tri, wtype, dn)
   with the index of the wall fix, the mesh and triangle (-1, -1 for a
   primitive wall), the wall's atom type and the signed distance dn of the
   sphere's surface from the wall (dn < 0: overlap -dn). A sphere at an edge
   shared by two triangles is visited once per triangle, with equal dn.
------------------------------------------------------------------------- */

#ifndef LMP_CRUSH_WALL_CONTACTS_H
#define LMP_CRUSH_WALL_CONTACTS_H

#include <vector>

#include "atom.h"
#include "fix_mesh_surface.h"
#include "fix_neighlist_mesh.h"
#include "fix_wall_gran.h"
#include "primitive_wall.h"
#include "tri_mesh.h"

namespace LAMMPS_NS {

template <class Keep, class Visit>
inline void for_each_wall_neighbour(const std::vector<FixWallGran *> &walls, Atom *atom, Keep keep, Visit visit)
{
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double delta_vec[3];
  for (size_t w = 0; w < walls.size(); w++) {
    FixWallGran *wall = walls[w];
    if (wall->is_mesh_wall()) {
      for (int im = 0; im < wall->n_meshes(); im++) {
        FixMeshSurface *fm = wall->mesh_list()[im];
        TriMesh *mesh = fm->triMesh();
        FixNeighlistMesh *nl = fm->meshNeighlist();
        if (!nl) continue;
        const int wtype = fm->atomTypeWall();
        const int ntri = mesh->sizeLocal() + mesh->sizeGhost();
        for (int t = 0; t < ntri; t++) {
          const std::vector<int> &cl = nl->get_contact_list(t);
          for (size_t c = 0; c < cl.size(); c++) {
            const int i = cl[c];
            if (i >= nlocal || !keep(i)) continue;
            int barysign;
            const double dn = mesh->resolveTriSphereContact(i, t, radius[i], x[i], delta_vec, barysign);
            visit(i, (int)w, im, t, wtype, dn);
          }
        }
      }
    } else {
      PrimitiveWall *pw = wall->primitiveWall();
      if (!pw) continue;
      const int wtype = wall->atom_type_wall();
      int *nb;
      const int n = pw->getNeighbors(nb);
      for (int k = 0; k < n; k++) {
        const int i = nb[k];
        if (i >= nlocal || !(mask[i] & wall->groupbit) || !keep(i)) continue;
        const double dn = pw->resolveContact(x[i], radius[i], delta_vec);
        visit(i, (int)w, -1, -1, wtype, dn);
      }
    }
  }
}

}  // namespace LAMMPS_NS

#endif
