"""Exceptions with one-line messages the CLI prints as they are."""

from __future__ import annotations


class InputError(ValueError):
    """A bad input value: names the field as the user wrote it, the value and what is allowed.

    Parameters
    ----------
    field : str
        Dotted path of the offending field, e.g. ``"disk.inertia"``.
    value : object
        The value given.
    allowed : str
        What would have been accepted, e.g. ``"a number > 0"``.
    mentions : tuple of str
        Keys named in ``allowed`` (``"max_dof"`` in "raise max_dof"), relative to the same table
        as ``field``: :meth:`relocated` moves them with it.
    """

    def __init__(self, field: str, value: object, allowed: str, mentions: tuple[str, ...] = ()):
        self.field, self.value, self.allowed, self.mentions = field, value, allowed, tuple(mentions)
        super().__init__(f"{field} = {shown(value)} is invalid: expected {allowed}")

    def relocated(self, prefix: str = "", rename: dict[str, str] | None = None) -> InputError:
        """This error with its key path as the user wrote it in the whole file.

        Parameters
        ----------
        prefix : str
            Dotted path of the table the field is relative to (``"rotor[0]"``); added unless
            the field already starts with it.
        rename : dict, optional
            Path prefixes to replace after that (``{"bearing[0]": "bearing.left"}`` where a
            table of named tables was read as a list).
        """

        def move(key: str) -> str:
            if prefix and not (key == prefix or key.startswith((prefix + ".", prefix + "["))):
                key = f"{prefix}.{key}"
            for old, new in (rename or {}).items():
                if key == old or key.startswith((old + ".", old + "[")):
                    key = new + key[len(old) :]
            return key

        allowed = self.allowed
        for m in self.mentions:
            allowed = allowed.replace(m, move(m))
        out = InputError(move(self.field), self.value, allowed, tuple(move(m) for m in self.mentions))
        out.__cause__ = self.__cause__
        return out


class CheckFailed(RuntimeError):
    """A result failed one of its own checks (energy balance, constraint residual, ...).

    Domains set ``status = "failed_check"`` on the result instead of raising when they can
    still save it; this exception is for callers that cannot.
    """


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)`` as typed, shortened in the middle when very long (a 400-digit integer);
    booleans as TOML spells them."""
    value = plain(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**limit:
        digits = str(abs(value))
        return f"{'-' if value < 0 else ''}{digits[:6]}...{digits[-3:]} ({len(digits)} digits)"
    text = repr(value)
    text = text.replace("\n", " ").replace("\r", " ")
    return text if len(text) <= limit else text[: limit - 20] + "..." + text[-15:]


def plain(value: object) -> object:
    """NumPy scalars and arrays as the Python numbers and lists the user typed (a message shows
    ``0.0``, not ``np.float64(0.0)``); anything else unchanged."""
    if type(value).__module__ == "numpy" and hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (list, tuple)) and any(type(v).__module__ == "numpy" for v in value):
        return type(value)(plain(v) for v in value)
    return value


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
