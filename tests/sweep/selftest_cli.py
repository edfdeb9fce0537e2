"""Test helper: the rotaflex CLI with the selftest case registered as domain "selftest"."""

import sys

from rotaflex.core import domains

domains.CASES.setdefault("selftest", "rotaflex.sweep._selftest_case")

if __name__ == "__main__":
    from rotaflex.cli import main

    sys.argv[0] = "rotaflex"
    main()
