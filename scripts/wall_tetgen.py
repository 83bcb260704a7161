#!/usr/bin/env python3
"""Do volume meshers accept heartmesh's myocardium walls? (session 26, not part of CI)

Tetrahedralizes each wall (an STL, OBJ or PLY written by `heartmesh myocardium`) with TetGen
(Si 2015, through the `tetgen` Python package) and prints the number of tetrahedra and their total
volume beside the surface's enclosed volume: TetGen refuses open, self-intersecting or
inconsistently oriented surfaces, and the two volumes agree when the solid is what it says.

Needs: pip install tetgen trimesh numpy (not on CI machines, hence not a test).
Usage:  scripts/wall_tetgen.py WALL.stl [WALL2.obj ...]
"""

import sys

import numpy as np
import tetgen
import trimesh


def main(paths):
    failed = 0
    for path in paths:
        mesh = trimesh.load(path, process=False, force="mesh")
        tet = tetgen.TetGen(np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int32))
        try:
            nodes, elems = tet.tetrahedralize(order=1, quality=False, nobisect=True)[:2]
        except RuntimeError as e:
            print(f"{path}: TetGen refused it: {e}")
            failed += 1
            continue
        p = nodes[elems]
        six_v = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
        print(
            f"{path}: {len(elems)} tetrahedra, {np.abs(six_v).sum() / 6000:.3f} ml; "
            f"surface encloses {mesh.volume / 1000:.3f} ml"
        )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
