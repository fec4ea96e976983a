"""The DEM pair of the tiled-measure CLI tests (cli_tiled_test.sh,
cli_tiled_shard_test.sh), as ESRI ASCII grids GDAL reads.

A: cells of 1 m with two round holes (one 30 cells across, at the default
size); B: cells of 0.97 m on a grid shifted by fractions of a cell, the
surface lowered by a smooth bump (the change, 3 pi 800 m3 = 7540 m3 at the
default size) and with a hole of its own; ll.asc/.prj: a geographic DEM for
one error. Usage: make_tiled_pair.py [SCALE] (1: A is 240 x 180 cells; the
holes and the bump scale with it).
"""
import math
import sys

scale = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0


def grid(name, columns, rows, x0, y0, cell, holes, bump):
    with open(name, "w") as f:
        f.write("ncols %d\nnrows %d\nxllcorner %.6f\nyllcorner %.6f\ncellsize %.6f\nNODATA_value -9999\n"
                % (columns, rows, x0, y0, cell))
        for r in range(rows):
            y = y0 + (rows - r - 0.5) * cell
            line = []
            for c in range(columns):
                x = x0 + (c + 0.5) * cell
                # holes and the bump about (1000, 5000), A's lower-left corner
                lx, ly = x - 1000, y - 5000
                if any((lx - hx) ** 2 + (ly - hy) ** 2 < hr * hr for hx, hy, hr in holes):
                    line.append("-9999")
                    continue
                z = 20 * math.sin(lx / 37) * math.cos(ly / 23) + 0.05 * lx
                z -= bump * math.exp(-((lx - 120 * scale) ** 2 + (ly - 90 * scale) ** 2) / (800 * scale * scale))
                line.append("%.4f" % z)
            f.write(" ".join(line) + "\n")


s = scale
grid("a.asc", round(240 * s), round(180 * s), 1000.0, 5000.0, 1.0,
     [(60 * s, 50 * s, 15 * s), (200 * s, 140 * s, 4 * s)], 0.0)
grid("b.asc", round(250 * s), round(190 * s), 997.3, 4996.6, 0.97, [(150 * s, 40 * s, 6 * s)], 3.0)
grid("ll.asc", 40, 30, 174.0, -36.9, 0.001, [], 0.0)
with open("ll.prj", "w") as f:
    f.write('GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
            'PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]]')
