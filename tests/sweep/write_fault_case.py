"""Case function for the tests of case files written by the workers: the selftest case whose
Result fails *while its files are written* (after ``result.nc`` was written into the working
directory), on request.

``data["fault"]``: ``""`` (none), ``"raise"`` or ``"kill"`` (SIGKILL of the worker process),
applied only while the file named by ``data["fault_flag"]`` exists, so that a test can let the
next run succeed by removing it.
"""

import os
import signal
from pathlib import Path

from rotaflex.core.result import Result
from rotaflex.sweep._selftest_case import run_case as selftest_case


class FaultyWriteResult(Result):
    """The selftest Result; its extra files fail as asked."""

    def __init__(self, dataset, fault: str, flag: str):
        super().__init__(dataset)
        self.fault, self.flag = fault, flag

    def write_extra(self, out_dir: Path) -> list[Path]:
        assert (out_dir / "result.nc").exists()  # the failure comes after result.nc
        if self.fault and Path(self.flag).exists():
            if self.fault == "kill":
                os.kill(os.getpid(), signal.SIGKILL)
            raise RuntimeError("write_extra asked to fail")
        return []


def run_case(data: dict) -> Result:
    base = {k: v for k, v in data.items() if k not in ("fault", "fault_flag")}
    return FaultyWriteResult(selftest_case(base).dataset, data.get("fault", ""), data.get("fault_flag", ""))
