"""Exceptions of the numeric core. Each carries a message that says what is wrong and where."""


class MachineSpecError(ValueError):
    """A machine description that cannot be right."""


class ComponentErrorSpecError(ValueError):
    """A component-error set that does not fit its machine (unknown name, NaN, ...)."""
