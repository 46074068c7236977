"""granary_h5: read the HDF5 output of `granary run` for one's own plots.

Reads only granary's output files, with h5py and numpy (Debian: python3-h5py).

    import sys; sys.path.insert(0, "figures")       # or copy this one file
    from granary_h5 import Output
    with Output("out/fig2.h5") as o:
        t = o.times("msd")                           # output times of the /msd group
        msd, se = o.msd(), o.msd_se()                # [nt x M]; se is None for one replica
        th = o.msd_theory()                          # [nt x M] or None when not written

Replicas: a run of R > 1 replicas writes for each observable X its mean over replicas (X), the
standard error of that mean (X_se) and, with keep_replicas, every replica (X_replicas, replica
first); the root attribute `nreplicas` says R. A run of one replica has only X. Every `*_se`
accessor here returns None when the file has no X_se, and `nreplicas` is 1 when the attribute is
absent, so the same code plots files of both kinds (error bars only where they exist).

Attributes are returned as `str` whether the file stores them as str or bytes, and numbers as
Python numbers. Units and descriptions of each dataset: `o.units(path)`, `o.description(path)`.
"""

import numpy as np
import h5py

__all__ = ["Output", "attr_str", "open_output"]


def attr_str(value):
    """An HDF5 attribute as str (bytes decoded as UTF-8, 1-element arrays unwrapped)."""
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.reshape(-1)[0]
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", "replace")
    return str(value)


def _attr_value(value):
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "SO":
            return [attr_str(v) for v in value.reshape(-1)]
        if value.size == 1:
            return value.reshape(-1)[0].item()
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


class Output:
    """One granary output file. Use as a context manager or call close()."""

    def __init__(self, path):
        self.path = str(path)
        self.file = h5py.File(self.path, "r")
        fmt = self.attr("format", "")
        if not fmt.startswith("granary-output"):
            self.file.close()
            raise ValueError("%s: not a granary output file (root attribute format = %r)"
                             % (self.path, fmt))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.file.close()

    # ---- attributes -------------------------------------------------------------------------
    def attr(self, name, default=None, path="/"):
        """Attribute `name` of the object at `path` (root by default), str for strings."""
        obj = self.file[path]
        if name not in obj.attrs:
            return default
        return _attr_value(obj.attrs[name])

    @property
    def attrs(self):
        """All root attributes as a dict (scene, title, seed, selector, nspecies, ...)."""
        return {k: _attr_value(v) for k, v in self.file.attrs.items()}

    @property
    def title(self):
        return self.attr("title", "")

    @property
    def scene(self):
        """The whole scene text the run was made from."""
        return self.attr("scene", "")

    @property
    def nspecies(self):
        return int(self.attr("nspecies", len(self.file["species/mass"])))

    @property
    def nreplicas(self):
        """Number of replicas R (1 for a file without the attribute)."""
        return int(self.attr("nreplicas", 1))

    @property
    def complete(self):
        return bool(self.attr("complete", 1))

    def units(self, path):
        return self.attr("units", "", path)

    def description(self, path):
        return self.attr("description", "", path)

    def label(self, path):
        """'description [units]' of a dataset, for axis labels."""
        u = self.units(path)
        return self.description(path) + (" [%s]" % u if u else "")

    # ---- datasets ---------------------------------------------------------------------------
    def has(self, path):
        return path in self.file

    def get(self, path, default=None):
        """Dataset `path` as a numpy array (default when absent)."""
        if path not in self.file:
            return default
        return self.file[path][()]

    def se(self, path):
        """Standard error of dataset `path` over replicas (`path`_se), None when absent."""
        return self.get(path + "_se")

    def replicas(self, path):
        """Per-replica values (`path`_replicas, replica first), None when not kept."""
        return self.get(path + "_replicas")

    def times(self, group=None):
        """Output times: of a group (/msd/time, ...) when given, else /time."""
        if group is not None and group + "/time" in self.file:
            return self.get(group + "/time")
        return self.get("time")

    # species
    def species(self, name):
        """/species/<name>: mass, sigma, density, T0, counts."""
        return self.get("species/" + name)

    @property
    def tau0(self):
        return self.attr("tau0", None, "species")

    # temperatures
    def T(self):
        return self.get("temperatures/T")

    def T_se(self):
        return self.se("temperatures/T")

    def T_theory(self):
        return self.get("temperatures/T_theory")

    def T_theory_sonine(self):
        """Sonine T_k(t) ([observables] theory_sonine = true; its level: sonine_level()), else None."""
        return self.get("temperatures/T_theory_sonine")

    def sonine_level(self):
        """"first" or "second": the Sonine level of T_theory_sonine (the attribute theory_sonine_level of
        /temperatures, written with [observables] sonine_order = 3), None without T_theory_sonine."""
        if "temperatures/T_theory_sonine" not in self.file:
            return None
        lev = self.attr("theory_sonine_level", "", path="temperatures")
        return "second" if lev.startswith("second") else "first"

    # mean squared displacements
    def msd(self):
        return self.get("msd/msd")

    def msd_se(self):
        return self.se("msd/msd")

    def msd_theory(self):
        return self.get("msd/msd_theory")

    def msd_total(self):
        return self.get("msd/msd_total")

    def msd_total_se(self):
        return self.se("msd/msd_total")

    def msd_total_theory(self):
        return self.get("msd/msd_total_theory")

    # time-averaged MSD
    def lags(self):
        return self.get("tamsd/lag")

    def tamsd(self):
        return self.get("tamsd/tamsd")

    def tamsd_se(self):
        return self.se("tamsd/tamsd")

    def tamsd_theory(self):
        return self.get("tamsd/tamsd_theory")

    # energies and counters
    def energy(self, name="e_kin"):
        return self.get("energy/" + name)

    def energy_se(self, name="e_kin"):
        return self.se("energy/" + name)

    def collisions(self):
        return self.get("stats/collisions")

    def collisions_se(self):
        return self.se("stats/collisions")


def open_output(path):
    """Output(path); a function for `with open_output(p) as o:`."""
    return Output(path)
