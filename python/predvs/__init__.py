"""predvs: the predictors of predvs from Python (docs/PYTHON.md).

The compiled part (predvs._predvs) binds the C++ library; names and error messages are the C++
ones (a bad parameter or an unknown predictor raises ValueError with the C++ message).

    >>> import predvs
    >>> p = predvs.make("kf-cv", channels=2, params={"q": 500.0, "r": 2.25})
    >>> p.update(0.0, [320.0, 240.0]); p.update(1 / 30, [321.0, float("nan")])
    >>> x, P = p.predict(0.1)          # x (channels, n_state), P (channels, n_state, n_state)

Units as in C++: positions in px, velocities in px/s, times in s.
"""
import os as _os
import tempfile as _tempfile

from ._predvs import (  # noqa: F401
    FittedValue,
    Innovation,
    NoiseFitResult,
    NoiseParameter,
    Predictor,
    fit_noise,
    fit_parameters,
    is_predictor,
    log_likelihood,
    make,
    params_file_text,
    predictors,
    read_params,
)

__all__ = [
    "FittedValue", "Innovation", "NoiseFitResult", "NoiseParameter", "Predictor", "fit_noise",
    "fit_parameters", "is_predictor", "log_likelihood", "make", "params_file_text", "predictors",
    "read_params", "write_params",
]


def write_params(path, entries, comment=()):
    """Writes a parameter file (the format `predvs fit-noise` writes, `--params FILE` reads).

    entries: [{"name": PREDICTOR, "params": {KEY: value}}] or a NoiseFitResult (its predictor and
    fitted params). Every entry is checked first (ValueError as read_params would raise); the file
    is written to a temporary sibling and renamed into place, so a failure leaves no half file.
    """
    if isinstance(entries, NoiseFitResult):
        entries = [{"name": entries.predictor, "params": entries.params}]
    text = params_file_text(list(entries), [str(c) for c in comment])
    folder = _os.path.dirname(_os.path.abspath(path))
    fd, tmp = _tempfile.mkstemp(prefix=".params-", suffix=".yaml", dir=folder)
    try:
        umask = _os.umask(0)
        _os.umask(umask)
        _os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it 0600; a parameter file is not a secret
        with _os.fdopen(fd, "w") as f:
            f.write(text)
        _os.replace(tmp, path)
    except BaseException:
        if _os.path.exists(tmp):
            _os.unlink(tmp)
        raise
