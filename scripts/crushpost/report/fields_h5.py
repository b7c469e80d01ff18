# SPDX-License-Identifier: GPL-2.0-or-later
"""fields.h5: the numbers behind every figure (layout: crushpost.formats,
docs/report.md)."""

import os

import numpy as np

from .. import formats as F


def _write_h5(rep, ctx):
    import h5py
    path = os.path.join(rep.out, "fields.h5")
    with h5py.File(path, "w") as f:
        run_dir, R, z_ref, units, problems = F.FIELDS_H5_ROOT_ATTRS
        f.attrs[run_dir] = os.path.abspath(rep.run)
        f.attrs[R] = ctx["R"]
        if ctx.get("z_ref") is not None:
            f.attrs[z_ref] = ctx["z_ref"]
        f.attrs[units] = "SI (m, Pa, s); angles in degrees; compression positive"
        for group, items in rep.h5.items():
            g = f.require_group(group)
            for k, v in items.items():
                g.create_dataset(k, data=np.asarray(v))
        for group, items in rep.h5_attrs.items():
            g = f.require_group(group)
            for k, v in items.items():
                g.attrs[k] = v
        h = f.require_group(F.FIELDS_H5_HEADLINE)
        for k, v in rep.head.items():
            h.attrs[k] = v
        f.attrs[problems] = "\n".join(m for _, m in rep.problems)
