"""The DEM pair of the tiled-measure CLI tests (cli_tiled_test.sh,
cli_tiled_shard_test.sh), as ESRI ASCII grids GDAL reads.

A: cells of 1 m with two round holes (one 30 cells across, at the default
size); B: cells of 0.97 m on a grid shifted by fractions of a cell, the
surface lowered by a smooth bump (the change, 3 pi 800 m3 = 7540 m3 at the
default size) and with a hole of its own; ll.asc/.prj: a geographic DEM for
one error; lla.asc/llb.asc (and .prj): two lon/lat DEMs on different grids.
Usage: make_tiled_pair.py [SCALE] (1: A is 240 x 180 cells; the
holes and the bump scale with it).
"""
import math
import sys

scale = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0


def grid(name, columns, rows, x0, y0, cell, holes, bump, local=None, bump_at=None):
    """`local` maps a cell centre to metres east and north of the point the
    holes and the bump are placed about (default: (1000, 5000), A's
    lower-left corner); `bump_at` is (x, y, width²) there."""
    local = local or (lambda x, y: (x - 1000, y - 5000))
    bx, by, width = bump_at or (120 * scale, 90 * scale, 800 * scale * scale)
    with open(name, "w") as f:
        f.write("ncols %d\nnrows %d\nxllcorner %.9f\nyllcorner %.9f\ncellsize %.9f\nNODATA_value -9999\n"
                % (columns, rows, x0, y0, cell))
        for r in range(rows):
            y = y0 + (rows - r - 0.5) * cell
            line = []
            for c in range(columns):
                lx, ly = local(x0 + (c + 0.5) * cell, y)
                if any((lx - hx) ** 2 + (ly - hy) ** 2 < hr * hr for hx, hy, hr in holes):
                    line.append("-9999")
                    continue
                z = 20 * math.sin(lx / 37) * math.cos(ly / 23) + 0.05 * lx
                z -= bump * math.exp(-((lx - bx) ** 2 + (ly - by) ** 2) / width)
                line.append("%.4f" % z)
            f.write(" ".join(line) + "\n")


s = scale
grid("a.asc", round(240 * s), round(180 * s), 1000.0, 5000.0, 1.0,
     [(60 * s, 50 * s, 15 * s), (200 * s, 140 * s, 4 * s)], 0.0)
grid("b.asc", round(250 * s), round(190 * s), 997.3, 4996.6, 0.97, [(150 * s, 40 * s, 6 * s)], 3.0)
WGS84 = ('GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
         'PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]]')
grid("ll.asc", 40, 30, 174.0, -36.9, 0.001, [], 0.0)
with open("ll.prj", "w") as f:
    f.write(WGS84)


# lla/llb: two lon/lat DEMs on different grids (cells of about 18 m).
def near_auckland(lon, lat):  # metres east and north of (174.7, -36.9), roughly
    return (lon - 174.7) * 89000.0, (lat + 36.9) * 111000.0


for name, columns, rows, lon0, lat0, cell, holes, bump in (
        ("lla", 120, 90, 174.7, -36.9, 0.0002, [(500, 600, 100)], 0.0),
        ("llb", 126, 95, 174.69993, -36.90004, 0.000195, [(1500, 900, 80)], 3.0)):
    grid(name + ".asc", columns, rows, lon0, lat0, cell, holes, bump, near_auckland, (1000, 800, 40000.0))
    with open(name + ".prj", "w") as f:
        f.write(WGS84)
