"""What the tests of scripts/ share: the script under test, a command run, and the arguments
(PREDVS WORKDIR) every such test takes."""
import os
import shutil
import subprocess
import sys

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts")


def script(name):
    """The path of scripts/NAME."""
    return os.path.join(SCRIPTS, name)


def run(cmd):
    """Runs cmd, output captured as text."""
    return subprocess.run(cmd, capture_output=True, text=True)


def checked(cmd):
    """Runs cmd and exits with its command line and error when it fails."""
    r = run(cmd)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {r.stderr.strip()}")
    return r


def refused_in_one_line(r, word=""):
    """True when the run r failed with a one-line error that contains word."""
    return r.returncode != 0 and len(r.stderr.strip().split("\n")) == 1 and word in r.stderr


def finish(failures, summary=None):
    """Exits with the failures, one per line, when there are any; else prints summary (if given)."""
    if failures:
        sys.exit("\n".join(failures))
    if summary is not None:
        print(summary)


def arguments():
    """PREDVS and WORKDIR from the command line; WORKDIR is made anew (a scratch directory of the
    build: what an earlier run left there, predvs would refuse to replace)."""
    if len(sys.argv) != 3:
        sys.exit(f"usage: {os.path.basename(sys.argv[0])} PREDVS WORKDIR")
    predvs, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    return predvs, work
