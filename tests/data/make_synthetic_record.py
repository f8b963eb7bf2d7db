"""Write ``synthetic.AT2``: a small synthetic accelerogram in the PEER NGA format, so that the
record paths of colonna are tested without downloading a real one.

Fourty sines between 0.5 and 8 Hz with random phases (seed 2012), shaped by the envelope
(t / 1.5 s)^2 exp(2 (1 - t / 1.5 s)) (peak at 1.5 s), scaled to a peak of 0.25 g; 6 s at
0.01 s. Run ``python tests/data/make_synthetic_record.py`` to regenerate it bit for bit.
"""

from pathlib import Path

import numpy as np

DT, DURATION, PEAK_G, SEED = 0.01, 6.0, 0.25, 2012


def synthetic_record():
    """(time (s), acceleration (g)) of the synthetic record."""
    rng = np.random.default_rng(SEED)
    t = np.arange(int(round(DURATION / DT))) * DT
    freqs = rng.uniform(0.5, 8.0, 40)
    phases = rng.uniform(0.0, 2.0 * np.pi, 40)
    signal = np.sin(2.0 * np.pi * freqs[:, None] * t[None, :] + phases[:, None]).sum(axis=0)
    envelope = (t / 1.5) ** 2 * np.exp(2.0 * (1.0 - t / 1.5))
    a = signal * envelope
    return t, PEAK_G * a / np.abs(a).max()


def write(path: Path) -> None:
    t, a = synthetic_record()
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD (format only)",
        "colonna synthetic record: 40 random-phase sines 0.5-8 Hz, envelope peak at 1.5 s",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {t.size}, DT= {DT:.4f} SEC",
    ]
    values = [f"{v: .7E}" for v in a]
    lines += ["  ".join(values[i : i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    write(Path(__file__).with_name("synthetic.AT2"))
