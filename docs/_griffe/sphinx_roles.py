"""Griffe extension for this site: Sphinx roles in the engine's docstrings.

The docstrings are NumPy style and cross-reference with Sphinx roles
(:func:`modal.correlations`, :class:`~modal.ModalWarning`), which Markdown
would print literally. They become inline code here; the docstrings stay as
they are, for ``help()`` and IDEs.
"""

from __future__ import annotations

import re

import griffe

ROLE = re.compile(r":(?:py:)?(?:func|class|meth|data|attr|mod|obj|exc|const):`~?([^`]+)`")


class SphinxRoles(griffe.Extension):
    def on_object(self, *, obj, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = ROLE.sub(r"`\1`", obj.docstring.value)
