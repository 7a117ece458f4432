"""Post-processing of kanesens run files (HDF5 layout: docs/reference/hdf5.md).

    from kanesens_post.io import open_run, design
    ds = open_run("out.h5")            # lazy xarray.Dataset, failed samples NaN
"""
__all__ = ["io", "distributions", "summary", "plot", "sobol", "morris", "dgsm", "linear_uq",
           "cli"]
