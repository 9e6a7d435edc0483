import subprocess
import sys

from sindy_impulse.cli import main


def test_demo_prints_equations_and_writes_figure(tmp_path, capsys):
    out_png = tmp_path / "demo.png"
    assert main(["demo", "--plot", str(out_png)]) == 0
    out = capsys.readouterr().out
    assert "After refinement (3 terms)" in out
    assert "-64.0000 x1 + -3.2000 x2" in out
    assert out_png.stat().st_size > 1000


def test_demo_with_noise_no_plot(capsys):
    assert main(["demo", "--snr", "30", "--plot", ""]) == 0
    assert "Stiffness k" in capsys.readouterr().out


def test_console_script_usage_error():
    proc = subprocess.run(
        [sys.executable, "-m", "sindy_impulse.cli", "nonsense"], capture_output=True, text=True
    )
    assert proc.returncode != 0
    assert "invalid choice" in proc.stderr
