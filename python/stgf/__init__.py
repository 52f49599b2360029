# SPDX-License-Identifier: Apache-2.0
"""stgf: multi-view collaborative object localization.

Several views (fixed cameras, connected vehicles) measure the 3D positions of the same objects,
each with its own noise; stgf fuses them into one estimate per object with a covariance you can
check. This package is the C++ library's Python face (pybind11 + NumPy).

Arrays are float64: for n measurements, ``time`` (n,), ``z`` (n, 3) and ``R`` (n, 3, 3), with
``view`` and ``object`` (and ``scene``) as n strings or one string for all. Estimates come back as
a dict with ``mean`` (n, 3) and ``covariance`` (n, 3, 3), one per measurement, in order.

    import stgf
    f = stgf.Filter()                       # constant-velocity prediction; Filter("model.pt") for Φ
    est = f.fuse(time=[0.0, 0.0], view=["cam1", "cam2"], object="walker",
                 z=[[1.0, 2.0, 0.0], [1.1, 2.1, 0.0]], R=[np.eye(3) * 0.01] * 2)
    est["mean"], est["covariance"]

Errors keep the C++ messages: bad files raise ``stgf.InputError`` ("FILE:LINE: what is wrong",
a ValueError), bad arrays ``ValueError``, a message later than the lag window under
``late_measurements: stop`` ``stgf.LateMeasurementError``.
"""

import numpy as _np

from ._stgf import (  # noqa: F401  (re-exported)
    Filter,
    InputError,
    LateMeasurementError,
    Model,
    __version__,
    evaluate,
    general_model,
    load_model,
    metrics,
    method_names,
    read_estimates,
    read_measurements,
    read_truth,
)
from . import _stgf

__all__ = [
    "Filter", "InputError", "LateMeasurementError", "Model", "__version__", "evaluate", "general_model", "load_model",
    "method_names", "metrics", "read_estimates", "read_measurements", "read_truth", "run", "run_file",
    "write_estimates",
]


def run(method, measurements, model=None, config=None):
    """Runs a method (aom, wls, mmt, sttp, ours-l, ours) over measurements of any number of scenes.

    ``measurements`` is a dict as read_measurements returns it (keys scene, time, view, object, z, R,
    and optionally arrival and sensor_position), or the path of a measurements CSV. ``ours`` factors
    each view's registration offset along the ray from its sensor when the sensor position is given. ``model`` (a path or a Model) is
    what sttp, ours-l and ours run; without one, ours and ours-l use the general model shipped with
    stgf (general_model(), models/README.md) and sttp is an error; ``config`` is the path of a YAML method settings file.
    Returns a dict: ``mean`` (n, 3), ``covariance`` (n, 3, 3), one per measurement in order, and
    ``report`` (restarted tracks, late rows fused in their place and the rewinds they took, late
    measurements left out, as the CLI logs them).
    """
    if isinstance(measurements, str):
        measurements = read_measurements(measurements)
    return _stgf.run(method, measurements["scene"], _np.asarray(measurements["time"], dtype=float),
                     measurements["view"], measurements["object"],
                     _np.asarray(measurements["z"], dtype=float), _np.asarray(measurements["R"], dtype=float),
                     arrival=measurements.get("arrival"), sensor_position=measurements.get("sensor_position"),
                     model=model, config=config)


def write_estimates(path, measurements, estimates, method):
    """Writes estimates (a dict with mean and covariance) for the rows of ``measurements`` to a CSV
    file in stgf's estimates format, whole or not at all."""
    _stgf.write_estimates(path, measurements["scene"], _np.asarray(measurements["time"], dtype=float),
                          measurements["view"], measurements["object"],
                          _np.asarray(estimates["mean"], dtype=float),
                          _np.asarray(estimates["covariance"], dtype=float), method)


def run_file(method, measurements_path, out_path, model=None, config=None):
    """``stgf run`` in-process: reads a measurements CSV, runs the method, writes the estimates CSV.
    Returns the estimates dict."""
    measurements = read_measurements(measurements_path)
    estimates = run(method, measurements, model=model, config=config)
    write_estimates(out_path, measurements, estimates, method)
    return estimates
