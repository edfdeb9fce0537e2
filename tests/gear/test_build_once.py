"""`gear simulate` builds its model once per run: validate_config and run_case share it."""

from rotaflex.gear.cases import simulate

CONFIG = {"operation": {"span_deg": 0.5}, "mesh": {"preset": "coarse"}, "output": {"every": 20, "root_stress": False}}


def test_validate_then_run_builds_the_model_once_and_a_fresh_run_builds_again(monkeypatch):
    calls = []
    real = simulate.build

    def counting(cfg):
        calls.append(cfg)
        return real(cfg)

    monkeypatch.setattr(simulate, "build", counting)
    simulate.validate_config(CONFIG)
    first = simulate.run_case(CONFIG)
    assert len(calls) == 1
    again = simulate.run_case(CONFIG)  # nothing validated for it: builds its own
    assert len(calls) == 2
    for name in ("contact_force", "rotation_angle"):
        assert (first.dataset[name].values == again.dataset[name].values).all()
