"""The forecast of an atlas made by augmentation from a stratified sample of its starts (domes.typesynth.strata)."""

from domes.typesynth import augment, strata


def test_the_estimate_is_exact_where_every_stratum_is_alike():
    # Starts of one stratum all "lead to" the same made-up chains and seconds: any sample gives the true totals,
    # of the whole and of each part (the strata's means times their starts, not a scaling by the parts walked).
    starts, parts = augment.plan(4, 3)                          # 12 links, DOF 3
    keys = [strata.stratum(g) for g in starts]
    value = {key: (len(key[1]) + 3 * key[0] + key[2], 0.01 * len(key[1])) for key in keys}
    said = []
    s = strata.sample(starts, 4, 3, budget=40, seed=3, walk=lambda i: value[keys[i]], strata=keys,
                      progress=said.append)
    assert s.walked == len(said) <= 40 + len(set(keys))
    assert s.chains() == sum(value[k][0] for k in keys)
    for i in range(parts):
        mine = range(i, len(starts), parts)
        assert s.chains(mine) == sum(value[keys[j]][0] for j in mine)
        assert abs(s.seconds(mine) - sum(value[keys[j]][1] for j in mine)) < 1e-9


def test_the_forecast_of_twelve_links_is_within_a_third():
    # 6,856 chains of 12 links with DOF 1 (the brief's table of chain counts; OEIS A233288).
    starts, _ = augment.plan(5, 1)
    s = strata.sample(starts, 5, 1, budget=100)
    assert 6856 / 1.3 < s.chains() < 6856 * 1.3
    assert s.walked < len(starts) and s.seconds() > s.seconds_walked > 0
