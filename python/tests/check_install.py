"""CTest python_from_install: the package installed by `cmake --install` (test install_prefix)
imports from PREFIX with PYTHONPATH=PREFIX/lib/python3/dist-packages, and works.
Usage: check_install.py PREFIX"""
import os
import sys

prefix = os.path.realpath(sys.argv[1])
import predvs  # noqa: E402

where = os.path.realpath(predvs.__file__)
assert where.startswith(prefix + os.sep), f"predvs imported from {where}, not from {prefix}"
p = predvs.make("kf-cv", 2, {"q": 100.0})
p.update(0.0, [1.0, 2.0])
p.update(0.1, [2.0, 3.0])
assert p.predict(0.2)[0].shape == (2, 2)
print("python_from_install: OK", where)
