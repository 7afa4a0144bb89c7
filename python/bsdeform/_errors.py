# SPDX-License-Identifier: MIT
"""Exceptions of the bsdeform package (raised by the C++ module too)."""


class Error(Exception):
    """Base class of bsdeform's errors."""


class FieldError(Error, ValueError):
    """A field value the node refused; the message names node, field and value."""


class SceneError(Error):
    """A scene that cannot be read: "FILE:LINE: reason", or Coin's read errors."""


class SimulationError(Error, RuntimeError):
    """The simulation blew up (the last finite state is kept) or refused a step."""


class RenderError(Error, RuntimeError):
    """Offscreen rendering or writing the image failed."""
