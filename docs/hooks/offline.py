"""MkDocs hook: the site is self-contained. A page that would load a script or a stylesheet from
the network (the notebooks' MathJax from a CDN; any such tag added later) loses that tag, and the
build fails (strict) if anything else on a page still loads from the network: the site works
offline and from ``file://``, and tells no third party who reads it."""

from __future__ import annotations

import logging
import re
from typing import Any

log = logging.getLogger("mkdocs.plugins.parakin.offline")

#: a <script src="http..."></script> or <link ... href="http..."> that loads a resource
EXTERNAL_SCRIPT = re.compile(r"<script\b[^>]*\bsrc=[\"']?(?:https?:)?//[^>]*>\s*</script>", re.IGNORECASE)
EXTERNAL_LINK = re.compile(
    r"<link\b(?=[^>]*\brel=[\"']?(?:stylesheet|preconnect|preload|dns-prefetch))[^>]*\bhref=[\"']?(?:https?:)?//[^>]*>",
    re.IGNORECASE,
)
#: anything else that a browser would fetch by itself: src= on img, iframe, script, source ...
LOADS = re.compile(
    r"<(?:img|iframe|script|source|video|audio|embed)\b[^>]*\bsrc=[\"']?(?:https?:)?//[^>]*>", re.IGNORECASE
)


def on_post_page(output: str, page: Any, config: Any) -> str:
    """``output`` without network scripts and stylesheets; an error for any other network load."""
    cleaned = EXTERNAL_LINK.sub("", EXTERNAL_SCRIPT.sub("", output))
    left = LOADS.search(cleaned)
    if left:
        log.warning("%s loads %s from the network: the site must be self-contained", page.file.src_uri, left[0][:200])
    return cleaned
