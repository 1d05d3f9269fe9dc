"""python3 -m nurbsgl: the package's command lines are its modules (python3 -m nurbsgl.dask)."""
import sys

sys.stderr.write("usage: python3 -m nurbsgl.dask distance [--scheduler ADDRESS] MODEL POINTS.npy -o OUT.npy\n"
                 "(the command-line tool for single-process work is `nurbsgl`)\n")
sys.exit(2)
