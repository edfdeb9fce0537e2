"""Exceptions with one-line messages the CLI prints as they are."""

from __future__ import annotations


class InputError(ValueError):
    """A bad input value: names the field, the value and what is allowed.

    Parameters
    ----------
    field : str
        Dotted path of the offending field, e.g. ``"disk.inertia"``.
    value : object
        The value given.
    allowed : str
        What would have been accepted, e.g. ``"a number > 0"``.
    """

    def __init__(self, field: str, value: object, allowed: str):
        self.field, self.value, self.allowed = field, value, allowed
        super().__init__(f"{field} = {shown(value)} is invalid: expected {allowed}")


class CheckFailed(RuntimeError):
    """A result failed one of its own checks (energy balance, constraint residual, ...).

    Domains set ``status = "failed_check"`` on the result instead of raising when they can
    still save it; this exception is for callers that cannot.
    """


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)`` as typed, shortened in the middle when very long (a 400-digit integer);
    booleans as TOML spells them."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**limit:
        digits = str(abs(value))
        return f"{'-' if value < 0 else ''}{digits[:6]}...{digits[-3:]} ({len(digits)} digits)"
    text = repr(value)
    text = text.replace("\n", " ").replace("\r", " ")
    return text if len(text) <= limit else text[: limit - 20] + "..." + text[-15:]


class ConvergenceError(RuntimeError):
    """An iterative solver did not reach its tolerance.

    Parameters
    ----------
    what : str
        Which iteration failed (e.g. ``"velocity pass"``).
    time : float
        Simulation time at failure [s].
    residual : float
        Residual norm reached.
    tolerance : float
        Tolerance asked for.
    """

    def __init__(self, what: str, time: float, residual: float, tolerance: float):
        self.what, self.time, self.residual, self.tolerance = what, time, residual, tolerance
        super().__init__(
            f"{what} did not converge at t = {time:.9g} s: residual {residual:.3e} > tolerance {tolerance:.3e}"
        )


class SingularityError(RuntimeError):
    """A parameterisation became singular (gimbal lock, singular mass matrix).

    Parameters
    ----------
    what : str
        Description of the singular quantity.
    time : float
        Time at which it was detected [s] (nan if not time dependent).
    detail : str
        Extra information, e.g. the angle values.
    """

    def __init__(self, what: str, time: float = float("nan"), detail: str = ""):
        self.what, self.time, self.detail = what, time, detail
        at = "" if time != time else f" at t = {time:.9g} s"
        super().__init__(f"{what} is singular{at}" + (f" ({detail})" if detail else ""))


class DivergenceError(RuntimeError):
    """A time integration left the finite numbers (unstable step or unbounded response).

    Parameters
    ----------
    what : str
        Which integration diverged.
    time : float
        Simulation time of the first non-finite state [s].
    detail : str
        What to try.
    """

    def __init__(self, what: str, time: float, detail: str = ""):
        self.what, self.time, self.detail = what, time, detail
        super().__init__(f"{what} diverged at t = {time:.9g} s" + (f": {detail}" if detail else ""))
