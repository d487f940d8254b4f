"""The build of the Rust extension this CPU runs fastest.

A wheel carries the extension twice: ``_geopid``, built for any x86-64
(SSE2), and ``_geopid_x86_64_v3``, built with AVX2 and FMA. The SIMD lanes
of the Monte Carlo choose their instructions when they are compiled, so the
choice between them is made here, once, at import: the x86-64-v3 build when
the CPU has every feature of that level (asked of ``cpuid`` by the baseline
build, which runs anywhere), the baseline build otherwise. Both give the
same results to the bit; only the time differs.

``GEOPID_INSTRUCTION_SET=baseline`` forces the baseline build (to compare
the two), ``x86-64-v3`` requires the other, ``auto`` (or unset) chooses. A
build from a checkout (``pip install ./python``) has one module, compiled
for the machine that built it.
"""

import importlib
import os
from types import ModuleType

from . import _geopid as _baseline

_VARIABLE = "GEOPID_INSTRUCTION_SET"


def _choose() -> ModuleType:
    want = os.environ.get(_VARIABLE, "auto") or "auto"
    if want not in ("auto", "baseline", "x86-64-v3"):
        raise ImportError(f"{_VARIABLE}={want!r}: expected auto, baseline or x86-64-v3")
    if want == "baseline":
        return _baseline
    if not _baseline.cpu_has_x86_64_v3():
        if want == "x86-64-v3":
            raise ImportError(f"{_VARIABLE}=x86-64-v3, but this CPU lacks AVX2, FMA or another x86-64-v3 feature")
        return _baseline
    fast_name = f"{__package__}._geopid_x86_64_v3"
    try:
        # `import_module`, not `from . import`: a missing submodule is then
        # a ModuleNotFoundError naming it, not an ImportError about the
        # package being initialised.
        fast = importlib.import_module(fast_name)
    except ModuleNotFoundError as e:
        if e.name != fast_name:
            raise
        if want == "x86-64-v3" and _baseline.instruction_set() != "x86-64-v3":
            raise ImportError(
                f"{_VARIABLE}=x86-64-v3, but this installation has one build of the extension "
                f"(built for {_baseline.instruction_set()})"
            ) from None
        return _baseline
    return fast


ext = _choose()
