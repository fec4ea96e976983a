#!/usr/bin/env python3
"""Builds the terrain example of configs/terrain_dem.yaml (run from the project root):

  configs/data/volcano_dem.tif        the Maunga Whau grid (87 x 61 cells of 10 m) as a
                                      GeoTIFF placed in NZTM2000 (EPSG:2193) near Mt Eden
  configs/data/volcano_dem_moved.tif  a second "survey": the same terrain moved by a known
                                      rigid motion (0.5/0.3/0.8 deg tilt and turn, a 12.3 /
                                      -7.9 / 2.5 m shift), resampled on a grid offset by a
                                      fraction of a cell, with N(0, 0.5 m) noise; cells that
                                      fall outside the original are nodata
  configs/data/volcano_dem_truth.txt  the true moving -> reference matrix (row-major)

The terrain between the grid nodes is a bicubic spline of the grid (scipy), so the moved
copy is not simply the reference's own piecewise-linear surface. Needs numpy, scipy and
gdal_translate (Debian gdal-bin); surfreg itself does not need them.
"""
import os
import subprocess
import numpy as np
from scipy.interpolate import RectBivariateSpline

HERE = os.path.dirname(os.path.abspath(__file__))
X0, Y0, CELL = 1756000.0, 5916500.0, 10.0   # outer corner (west, south) of the grid, NZTM
NOISE = 0.50
SEED = 20261121

def load_volcano():
    rows = [l.split() for l in open(os.path.join(HERE, 'volcano.xyz')) if l[0] not in '#']
    p = np.array(rows, dtype=float)
    nx, ny = 87, 61
    z = np.zeros((nx, ny))
    for x, y, h in p:
        z[int(round(x / 10)), int(round(y / 10))] = h
    return z  # z[i, j] at x = 10 i, y = 10 j (metres from the first node)

def rotation(rx, ry, rz):
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx

def write_asc(path, grid, x_corner, y_corner, cell, nodata=-9999.0):
    rows, cols = grid.shape
    with open(path, 'w') as f:
        f.write(f'ncols {cols}\nnrows {rows}\nxllcorner {x_corner:.6f}\nyllcorner {y_corner:.6f}\n')
        f.write(f'cellsize {cell}\nNODATA_value {nodata}\n')
        for r in range(rows):
            f.write(' '.join('%.4f' % (nodata if np.isnan(v) else v) for v in grid[r]) + '\n')

def to_geotiff(asc, tif):
    subprocess.run(['gdal_translate', '-q', '-of', 'GTiff', '-a_srs', 'EPSG:2193', '-ot', 'Float32',
                    '-co', 'COMPRESS=DEFLATE', asc, tif], check=True)
    os.remove(asc)

def main():
    z = load_volcano()
    nx, ny = z.shape
    # Node (i, j) is the centre of raster cell (column i, row ny-1-j).
    xs = X0 + CELL * (np.arange(nx) + 0.5)
    ys = Y0 + CELL * (np.arange(ny) + 0.5)
    terrain = RectBivariateSpline(xs, ys, z, kx=3, ky=3)
    reference = z.T[::-1, :]  # rows north to south
    write_asc(os.path.join(HERE, 'volcano_dem.asc'), reference, X0, Y0, CELL)
    to_geotiff(os.path.join(HERE, 'volcano_dem.asc'), os.path.join(HERE, 'volcano_dem.tif'))

    # The true motion M (moving -> reference): p_ref = R (q - c) + c + t.
    R = rotation(*np.radians([0.5, 0.3, 0.8]))
    c = np.array([X0 + 435.0, Y0 + 305.0, 140.0])
    t = np.array([12.3, -7.9, 2.5])
    M = np.eye(4)
    M[:3, :3] = R
    M[:3, 3] = c + t - R @ c
    # The moving survey: a grid offset by (0.37, 0.62) cells; at each cell centre (x, y) its
    # height z solves (M q).z = terrain((M q).xy) for q = (x, y, z) (Newton steps).
    mx0, my0 = X0 + 0.37 * CELL - 30.0, Y0 + 0.62 * CELL - 20.0
    cols, rows = nx + 4, ny + 3
    rng = np.random.default_rng(SEED)
    moving = np.full((rows, cols), np.nan)
    for r in range(rows):
        for col in range(cols):
            x = mx0 + CELL * (col + 0.5)
            y = my0 + CELL * (rows - r - 0.5)
            h = 140.0
            for _ in range(30):
                p = M @ np.array([x, y, h, 1.0])
                g = p[2] - terrain(p[0], p[1])[0, 0]
                dg = M[2, 2] - (terrain(p[0], p[1], dx=1)[0, 0] * M[0, 2] +
                                terrain(p[0], p[1], dy=1)[0, 0] * M[1, 2])
                h -= g / dg
                if abs(g) < 1e-9:
                    break
            p = M @ np.array([x, y, h, 1.0])
            inside = xs[0] <= p[0] <= xs[-1] and ys[0] <= p[1] <= ys[-1]
            if inside:
                moving[r, col] = h + rng.normal(0.0, NOISE)
    write_asc(os.path.join(HERE, 'volcano_dem_moved.asc'), moving, mx0, my0, CELL)
    to_geotiff(os.path.join(HERE, 'volcano_dem_moved.asc'), os.path.join(HERE, 'volcano_dem_moved.tif'))
    with open(os.path.join(HERE, 'volcano_dem_truth.txt'), 'w') as f:
        f.write('# true moving -> reference matrix of volcano_dem_moved.tif (row-major)\n')
        f.write(', '.join('%.17g' % v for v in M.ravel()) + '\n')
    print('known matrix:', ', '.join('%.17g' % v for v in M.ravel()))
    print('moving cells with data:', int(np.sum(~np.isnan(moving))), 'of', moving.size)

if __name__ == '__main__':
    main()
