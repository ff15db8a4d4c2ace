"""The sources the course quotes, as full citations, and which of them a page names.

The lessons call their sources by short names ("the LPV paper", "Kirsch's annotations",
"the DX11 article"; lesson 1 lists them). Each lesson page ends with the citations of the
sources its text names, after the two papers that define the method, which every page
is about. Addresses are printed as text, not links: the site reads without a network.
"""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Reference:
    key: str
    citation: str
    """Authors, title, where and when (plain text; the title in quotes)."""
    names: str
    """A regular expression for how the lessons name it (case-insensitive)."""
    address: str = ""
    always: bool = False
    """Cited on every lesson page (the papers that define the method)."""


REFERENCES: tuple[Reference, ...] = (
    Reference("lpv-2009",
              'Anton Kaplanyan. "Light Propagation Volumes in CryEngine 3". In Advances in '
              "Real-Time Rendering in 3D Graphics and Games, SIGGRAPH 2009 course, Crytek, "
              "2009.",
              r"\bthe LPV paper\b|\bCryEngine\b",
              "http://www.crytek.com/download/Light_Propagation_Volumes.pdf", always=True),
    Reference("clpv-2010",
              'Anton Kaplanyan and Carsten Dachsbacher. "Cascaded Light Propagation Volumes '
              'for Real-Time Indirect Illumination". In Proceedings of the 2010 ACM '
              "SIGGRAPH Symposium on Interactive 3D Graphics and Games (I3D '10), "
              "pp. 99–107, ACM, 2010. doi:10.1145/1730804.1730821.",
              r"\bcascaded-LPV paper\b|\bKaplanyan\b|\bDachsbacher\b",
              "http://www.crytek.com/download/20100301_lpv.pdf", always=True),
    Reference("kirsch-annotations",
              'Andreas Kirsch. "Light Propagation Volumes — Annotations". 17 July 2010.',
              r"\bKirsch\b|\bannotations\b", "http://blog.blackhc.net/2010/07/"
              "light-propagation-volumes/"),
    Reference("kirsch-corrections",
              'Andreas Kirsch. "Light Propagation Volumes — Corrections". 17 July 2010.',
              r"\bKirsch\b|\bthe (?:three )?corrections\b",
              "http://blog.blackhc.net/2010/07/light-propagation-volumes/"),
    Reference("rsm-2005",
              'Carsten Dachsbacher and Marc Stamminger. "Reflective Shadow Maps". In '
              "Proceedings of the 2005 Symposium on Interactive 3D Graphics and Games "
              "(I3D '05), pp. 203–231, ACM, 2005. doi:10.1145/1053427.1053460.",
              r"\breflective shadow maps?\b|\bRSMs?\b"),
    Reference("dx11-article",
              '"Light Propagation Volumes": a DirectX 11 implementation article with its '
              "full shaders (a school project; the copy the project worked from names no "
              "author or date). Quoted here as the DX11 article.",
              r"\bDX11\b|\bDirectX 11\b"),
    Reference("dx12-blog",
              '"Light Propagation Volumes": a DirectX 12 implementation write-up with a build '
              "and its source (the copy the project worked from names no author or date). "
              "Quoted here as the DX12 write-up.",
              r"\bDX12\b|\bDirectX 12\b"),
    Reference("mitsuba-3",
              "Wenzel Jakob, Sébastien Speierer, Nicolas Roussel, Merlin Nimier-David, "
              'Delio Vicini, Tizian Zeltner, Baptiste Nicolet, Miguel Crespo, Vincent '
              'Leroy and Ziyi Zhang. "Mitsuba 3 renderer". 2022.',
              r"\bMitsuba\b", "https://mitsuba-renderer.org"),
)


def cited(text: str) -> list[Reference]:
    """The references a page with ``text`` (what its reader reads) cites, in the order
    of :data:`REFERENCES`: those always cited and those the text names."""
    return [ref for ref in REFERENCES
            if ref.always or re.search(ref.names, text, re.I)]
