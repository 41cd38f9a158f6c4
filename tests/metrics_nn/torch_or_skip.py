"""Imported first by the tests that need Debian's python3-torch and python3-torchvision: without
them a test exits 77 (skipped) with the reason, except in CI, which installs them
(tools/run-tests.sh), where their absence is a failure."""
import os
import sys

try:
    import torch  # noqa: F401
    import torchvision  # noqa: F401
except ImportError as e:
    if os.environ.get("CI") == "true":
        sys.exit("FAIL: python3-torch / python3-torchvision missing in CI (%s)" % e)
    print("SKIP: needs python3-torch and python3-torchvision (%s); tools/run-tests.sh installs them" % e)
    sys.exit(77)
