"""Errors a user can act on. The CLI prints them as one line and exits with their code."""


class CityshadeError(Exception):
    """An error with a message meant for the user and a process exit code: 2, bad input, unless
    a subclass says otherwise."""

    exit_code = 2

    def __init__(self, message: str, exit_code: int | None = None):
        super().__init__(message)
        if exit_code is not None:
            self.exit_code = exit_code


class UsageError(CityshadeError):
    """A bad command-line value or input file (exit code 2, like argparse)."""


class Finding(CityshadeError):
    """A check found a problem in well-formed input (`grammar check`, `compress --verify`): exit code 1."""

    exit_code = 1


class GLUnavailableError(CityshadeError):
    """No OpenGL 4.3 context could be created: the machine, not the input (exit code 1)."""

    exit_code = 1


class ShaderError(CityshadeError):
    """A GLSL file failed to compile or link; the message names file and line (exit code 1)."""

    exit_code = 1
