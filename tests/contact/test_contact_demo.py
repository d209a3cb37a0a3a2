from bearing_envelope.cli import main


def test_contact_demo_prints_hertz_comparison(capsys):
    assert main(["contact-demo", "--n", "32", "--force", "50"]) == 0
    out = capsys.readouterr().out
    assert "p0 (Pa)" in out and "a (m)" in out and "rel. error" in out


def test_contact_demo_rejects_tiny_grid(capsys):
    assert main(["contact-demo", "--n", "4"]) == 2
    assert "--n must be >= 8" in capsys.readouterr().err
