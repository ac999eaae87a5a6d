#!/usr/bin/env python3
"""Generates the game sounds in sounds/ (mono 16-bit WAV, 22050 Hz) from plain synthesis.

The sounds are the project's own: no recording, no third-party material. Run it again to
remake them; the output is the same on every run (fixed seed).
"""
import math
import os
import random
import struct
import wave

RATE = 22050
OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sounds")


def write(name, samples):
    path = os.path.join(OUT, name)
    with wave.open(path, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(RATE)
        w.writeframes(b"".join(struct.pack("<h", int(max(-1.0, min(1.0, s)) * 32767)) for s in samples))


def hit():
    """A mallet meeting the puck: a short knock, low tone plus a noise click."""
    rng = random.Random(1)
    n = int(0.09 * RATE)
    return [0.8 * math.exp(-t / (0.018 * RATE)) * (0.7 * math.sin(2 * math.pi * 190 * t / RATE) + 0.3 * rng.uniform(-1, 1))
            for t in range(n)]


def wall():
    """The puck off a wall: a brighter, shorter click."""
    rng = random.Random(2)
    n = int(0.05 * RATE)
    return [0.6 * math.exp(-t / (0.008 * RATE)) * (0.6 * math.sin(2 * math.pi * 880 * t / RATE) + 0.4 * rng.uniform(-1, 1))
            for t in range(n)]


def goal():
    """A goal horn: a major chord swelling in and out over 0.9 s."""
    n = int(0.9 * RATE)
    out = []
    for t in range(n):
        env = min(1.0, t / (0.05 * RATE), (n - t) / (0.15 * RATE))
        s = sum(math.sin(2 * math.pi * f * t / RATE) + 0.3 * math.sin(4 * math.pi * f * t / RATE) for f in (220, 277.2, 329.6))
        out.append(0.22 * env * s)
    return out


def whistle():
    """A drop: a referee's two-tone trill for 0.35 s."""
    n = int(0.35 * RATE)
    out = []
    for t in range(n):
        f = 2300 if (t // int(0.025 * RATE)) % 2 == 0 else 2650
        env = min(1.0, t / (0.01 * RATE), (n - t) / (0.03 * RATE))
        out.append(0.5 * env * math.sin(2 * math.pi * f * t / RATE))
    return out


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    for name, make in (("hit.wav", hit), ("wall.wav", wall), ("goal.wav", goal), ("whistle.wav", whistle)):
        write(name, make())
        print("wrote", os.path.join("sounds", name))
