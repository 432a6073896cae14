#!/usr/bin/env bash
# The wheels the GPU benchmark needs beyond what the project's GPU machines carry (numba, numba-cuda,
# numpy, scipy, xarray, pandas, matplotlib, h5py, click, tqdm, pyyaml, ... : docs/performance.md),
# for Python 3.12 on x86-64 Linux, into the git-ignored folder .whl/ of the repository. All are pure
# Python. The GPU run (benchmarks/gpu.py's docstring) installs them with
#   pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl && export PYTHONPATH=/tmp/site:$PWD/src
# Needed on that path: h5netcdf (the result stores), tomli-w (a store's config text); pint and its
# needs (units, imported when a quantity is parsed), npTDMS (measured records; light, so it travels
# too). Dask is not needed there: a GPU study runs in the calling process.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p .whl
grep -qx '/.whl/' .gitignore 2>/dev/null || echo '/.whl/' >> .gitignore
python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
    --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 \
    -d .whl \
    h5netcdf==1.8.2 tomli-w==1.2.0 pint==0.25.3 flexcache==0.3 flexparser==0.4 platformdirs==4.14.8 npTDMS==1.13.0
ls -l .whl
du -sh .whl
