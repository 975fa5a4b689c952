#!/usr/bin/python3
"""plcsweep: scenario campaigns of a cell in virtual time (docs/campaigns.md).

Installed as bin/plcsweep; the package is in share/softplc/python/ beside it
(or next to this file in the source tree). Debian's python3 (/usr/bin), for
python3-yaml, python3-matplotlib and python3-distributed."""
import os
import sys

here = os.path.dirname(os.path.realpath(__file__))
for cand in (os.path.join(here, "..", "share", "softplc", "python"), here):
    if os.path.isdir(os.path.join(cand, "plcsweep")):
        sys.path.insert(0, os.path.normpath(cand))
        break

from plcsweep.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
