"""Write the records that bundled examples read (vstpetsc/examples/*.csv).

site-response-motion.csv: a synthetic rock-outcrop acceleration, not a
recorded earthquake: band-limited random velocity (0.3 to 12 Hz, fixed
seed) under a smooth envelope that starts and ends at rest, scaled to a peak
acceleration of 1 m/s^2 (about 0.1 g), differentiated into an acceleration
sampled at 200 Hz for 16 s.  Its trapezoidal integral (what `integrate =
true` computes) returns to rest at the end.

sliding-block-ground.csv: the ground acceleration under the sliding block,
one cycle of 3 sin(2 pi t) m/s^2, then 2 s at rest (a velocity pulse, the
kind of near-fault motion that makes a block slide one way).

dam-interface-motion.csv: the two outcrop accelerations of the dam-interface
example, bursts of sines under a sin^2 envelope over 2 s, then rest:
horizontal 6 sin(2 pi 2 t), vertical 14 sin(2 pi 3 t) m/s^2.

nonlinear-site-motion.csv: a synthetic earthquake-like rock-outcrop
acceleration for the nonlinear-site example, Boore's (2003) stochastic
recipe: Gaussian noise (fixed seed) under a Saragoni-Hart envelope
(t^a exp(-b t), peak at 2.5 s, down to 5 % at 9 s), its Fourier amplitudes
shaped by a Brune omega-squared source spectrum
(corner frequency 0.3 Hz) with high-frequency decay exp(-pi kappa f)
(kappa = 0.04 s) and a 0.1 Hz low-cut, 12 s at 200 Hz, tapered at both
ends, its trapezoidal integral returning to rest at the end, scaled to a
peak of 1 g = 9.81 m/s^2 (a case's `scale` is then the peak in g).

rockfill-column-motion.csv: the two outcrop accelerations of the
rockfill-column example, each made as nonlinear-site-motion.csv's (peak
1 g) but 8 s long, from two seeds, the vertical with a corner frequency
of 1 Hz (richer in short periods, as vertical records are).

uplift-base.csv: the base velocity of the uplift example, 0.5 (1 - cos(2 pi 5
t)) m/s for two cycles, then at rest, sampled at 2 kHz (its acceleration
0.5 w sin(w t) starts from zero).

    python docs/make_example_records.py
"""

import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
FOLDER = os.path.join(HERE, "..", "vstpetsc", "examples")
DT, DURATION, BAND, PEAK = 0.005, 16.0, (0.3, 12.0), 1.0


def record(seed=20261123, duration=DURATION, peak=PEAK):
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + DT / 2, DT)
    spectrum = np.fft.rfft(rng.normal(size=t.size))
    f = np.fft.rfftfreq(t.size, DT)
    spectrum[(f < BAND[0]) | (f > BAND[1])] = 0.0
    velocity = np.fft.irfft(spectrum, t.size)
    scale = duration / DURATION
    envelope = np.sin(np.pi * t / duration) ** 2 * np.exp(-((t - 5.0 * scale)
                                                            / (4.0 * scale)) ** 2)
    velocity *= envelope
    acc = np.gradient(velocity, DT)
    acc *= peak / np.abs(acc).max()
    # trapezoidal integral from 0 ends at rest: remove its mean slope
    v = np.concatenate(([0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * DT)))
    acc -= v[-1] / duration
    return t, acc


def earthquake(seed=20260228, duration=12.0, corner=0.3, kappa=0.04, low_cut=0.1):
    """(t, acc) of nonlinear-site-motion.csv: peak 1 g, ends at rest."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + DT / 2, DT)
    # Saragoni-Hart envelope t^a exp(-b t): largest at a / b, 5 % of it at 9 s
    a = 2.0
    b = a / 2.5
    envelope = (t * b / a) ** a * np.exp(a - b * t)
    spectrum = np.fft.rfft(rng.normal(size=t.size) * envelope)
    f = np.fft.rfftfreq(t.size, DT)
    shape = f ** 2 / (1.0 + (f / corner) ** 2) * np.exp(-np.pi * kappa * f)
    shape *= 1.0 / (1.0 + (low_cut / np.maximum(f, 1e-12)) ** 8)     # Butterworth low-cut
    acc = np.fft.irfft(spectrum * shape, t.size)
    # start and end at rest: half-cosine tapers over the first 0.5 s and the last 1 s
    acc *= np.sin(np.pi / 2 * np.clip(np.minimum(t / 0.5, (duration - t) / 1.0), 0, 1)) ** 2
    return t, _at_rest(acc, duration, 9.81)


def _at_rest(acc, duration, peak):
    """acc less the constant that makes its trapezoidal integral end at
    zero, then scaled to ``peak``."""
    v = np.concatenate(([0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * DT)))
    acc = acc - v[-1] / duration
    return acc * peak / np.abs(acc).max()


def dam_motion():
    """(t, horizontal, vertical) of dam-interface-motion.csv."""
    t = np.arange(0.0, 3.0 + DT / 2, DT)
    envelope = np.where(t <= 2.0, np.sin(np.pi * t / 2.0) ** 2, 0.0)
    return (t, 6.0 * np.sin(2 * np.pi * 2.0 * t) * envelope,
            14.0 * np.sin(2 * np.pi * 3.0 * t) * envelope)


def rockfill_motion():
    """(t, horizontal, vertical) of rockfill-column-motion.csv."""
    t, horizontal = earthquake(seed=20261129, duration=8.0)
    _, vertical = earthquake(seed=20261130, duration=8.0, corner=1.0)
    return t, horizontal, vertical


def write(name, header, t, *columns):
    path = os.path.join(FOLDER, name)
    with open(path, "w") as out:
        out.write(header + "\n")
        out.writelines(f"{a:.4f}," + ",".join(f"{b:.6e}" for b in row) + "\n"
                       for a, row in zip(t, zip(*columns)))
    print(f"wrote {path}: {t.size} samples, peaks "
          f"{', '.join(f'{np.abs(c).max():.4g}' for c in columns)}")


def main():
    write("site-response-motion.csv", "time,acc", *record())
    t = np.arange(0.0, 3.0 + DT / 2, DT)
    write("sliding-block-ground.csv", "time,acc", t,
          np.where(t <= 1.0, 3.0 * np.sin(2 * np.pi * t), 0.0))
    write("nonlinear-site-motion.csv", "time,acc", *earthquake())
    write("dam-interface-motion.csv", "time,horizontal,vertical", *dam_motion())
    write("rockfill-column-motion.csv", "time,horizontal,vertical", *rockfill_motion())
    t = np.arange(0.0, 0.45 + 1e-9, 0.0005)
    write("uplift-base.csv", "time,velocity", t,
          np.where(t <= 0.4, 0.5 * (1 - np.cos(2 * np.pi * 5 * t)), 0.0))


if __name__ == "__main__":
    main()
