"""Figures from results: each module draws one family of figures with matplotlib (Agg backend).

Plotting knows nothing of Dask or numba; it takes arrays, result objects or datasets.
"""
