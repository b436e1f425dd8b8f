"""The sphere's fluid-load tables (models.sphere): D(s) of a Hill truncation cut out of a cached
table equals D(s) computed at the truncation's own frequencies, bitwise, for both kinds and
truncations on either side of a table boundary; other s are computed afresh."""

import numpy as np
import pytest

from spectralshell.discretise.fourier import frequencies, real_indices, two_sided_indices
from spectralshell.models import sphere


def fresh(s, m, kappa, nu):
    out = sphere._fluid_values(m, nu, s)
    q = kappa * (m - 1) * (m + 2)
    out[:, 0, 0] += q
    out[:, 1, 1] += q
    return out


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("m, nu", [(2, 2.4e-4), (6, 1.3e-3)])
def test_truncations_equal_fresh_values(kind, m, nu):
    sphere._fluid_table.cache_clear()
    for n in (3, 15, 16, 17, 40, 175):
        for s in (frequencies(kind, two_sided_indices(kind, n)),
                  frequencies(kind, real_indices(n))):
            cached = sphere.poloidal_unforced(s, m=m, kappa=0.7, nu=nu)
            np.testing.assert_array_equal(cached, fresh(s, m, 0.7, nu))
    assert sphere._fluid_table.cache_info().hits > 0  # the tables were shared


def test_other_frequencies_are_computed_afresh():
    sphere._fluid_table.cache_clear()
    s = frequencies("harmonic", two_sided_indices("harmonic", 10)) + 0.3
    np.testing.assert_array_equal(sphere.poloidal_unforced(s, m=3, kappa=0.2, nu=1e-3),
                                  fresh(s, 3, 0.2, 1e-3))
    assert sphere._fluid_table.cache_info().currsize == 0

