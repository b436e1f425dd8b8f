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



@pytest.mark.parametrize("m, nu", [(2, 2.4e-4), (6, 1.3e-3), (40, 1e-2), (3, 1e-99)])
def test_unchecked_ratios_equal_checked_ones(m, nu):
    """special.spherical.ratio_pair (the tables' path, without the per-call domain checks)
    equals ratio_i(m, beta) and ratio_k(m - 1, beta) bitwise on both kinds' frequencies; the
    tables' values equal the checked computation bitwise."""
    from spectralshell.special.spherical import ratio_i, ratio_k, ratio_pair

    for kind in ("harmonic", "subharmonic"):
        s = frequencies(kind, two_sided_indices(kind, 60))
        s = s[s != 0]
        beta = np.sqrt(s / nu)
        r_i, r_k = ratio_pair(m, beta)
        np.testing.assert_array_equal(r_i, ratio_i(m, beta))
        np.testing.assert_array_equal(r_k, ratio_k(m - 1, beta))
    sphere._fluid_table.cache_clear()
    for gamma, (table_s, table) in zip(sphere.FLUID_GAMMAS, sphere._fluid_table(m, nu, 64)):
        assert table_s[0].imag == gamma - 65
        np.testing.assert_array_equal(table, sphere._fluid_values(m, nu, table_s.copy()))


def test_one_table_serves_both_kinds():
    """A harmonic and a subharmonic truncation of one (m, nu) share one table (one Bessel
    evaluation), and a larger truncation doubles its top rather than adding a step."""
    sphere._fluid_table.cache_clear()
    for kind in ("harmonic", "subharmonic"):
        s = frequencies(kind, two_sided_indices(kind, 20))
        sphere.poloidal_unforced(s, m=4, kappa=0.3, nu=1e-3)
    assert sphere._fluid_table.cache_info().currsize == 1
    s = frequencies("harmonic", two_sided_indices("harmonic", 40))
    np.testing.assert_array_equal(sphere.poloidal_unforced(s, m=4, kappa=0.3, nu=1e-3),
                                  fresh(s, 4, 0.3, 1e-3))
    assert sphere._fluid_table.cache_info().currsize == 2  # tops 32 and 64
    before = sphere._fluid_table.cache_info().hits
    sphere._fluid_table(4, 1e-3, 64)
    assert sphere._fluid_table.cache_info().hits == before + 1


def test_out_of_range_viscosity_keeps_the_checks():
    """Where nu lies outside the validated range the tables take the checked kernels, which
    refuse an argument beta beyond their domain (no unchecked value reaches a user)."""
    from spectralshell.errors import ParameterError

    sphere._fluid_table.cache_clear()
    s = frequencies("harmonic", two_sided_indices("harmonic", 10))
    with pytest.raises(ParameterError, match="nu"):
        sphere.poloidal_unforced(s, m=3, kappa=0.2, nu=1e-302)
