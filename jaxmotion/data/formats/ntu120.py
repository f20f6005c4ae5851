"""NTU RGB+D 120: its 120 action names, ActFormer's one-person (94) and two-person (26) label orders, and
its cross-subject split (FACTS 1.3).

ActFormer's preparation (AF:datasets/ntu120/prepare_ntu_data.py) keeps the 26 mutual actions A050-A060 and
A106-A120 as the two-person set, relabelled 0..25 in that order, and the other 94 as the one-person set in
ascending action order (A061-A105 become labels 49..93).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

#: NTU action id (1..120) -> its name, as the dataset's action list gives it.
ACTION_NAMES = {
    1: "drink water", 2: "eat meal/snack", 3: "brushing teeth", 4: "brushing hair", 5: "drop", 6: "pickup",
    7: "throw", 8: "sitting down", 9: "standing up (from sitting position)", 10: "clapping", 11: "reading",
    12: "writing", 13: "tear up paper", 14: "wear jacket", 15: "take off jacket", 16: "wear a shoe",
    17: "take off a shoe", 18: "wear on glasses", 19: "take off glasses", 20: "put on a hat/cap",
    21: "take off a hat/cap", 22: "cheer up", 23: "hand waving", 24: "kicking something", 25: "reach into pocket",
    26: "hopping (one foot jumping)", 27: "jump up", 28: "make a phone call/answer phone",
    29: "playing with phone/tablet", 30: "typing on a keyboard", 31: "pointing to something with finger",
    32: "taking a selfie", 33: "check time (from watch)", 34: "rub two hands together", 35: "nod head/bow",
    36: "shake head", 37: "wipe face", 38: "salute", 39: "put the palms together", 40: "cross hands in front (say stop)",
    41: "sneeze/cough", 42: "staggering", 43: "falling", 44: "touch head (headache)",
    45: "touch chest (stomachache/heart pain)", 46: "touch back (backache)", 47: "touch neck (neckache)",
    48: "nausea or vomiting condition", 49: "use a fan (with hand or paper)/feeling warm",
    50: "punching/slapping other person", 51: "kicking other person", 52: "pushing other person",
    53: "pat on back of other person", 54: "point finger at the other person", 55: "hugging other person",
    56: "giving something to other person", 57: "touch other person's pocket", 58: "handshaking",
    59: "walking towards each other", 60: "walking apart from each other",
    61: "put on headphone", 62: "take off headphone", 63: "shoot at the basket", 64: "bounce ball",
    65: "tennis bat swing", 66: "juggling table tennis balls", 67: "hush (quite)", 68: "flick hair", 69: "thumb up",
    70: "thumb down", 71: "make ok sign", 72: "make victory sign", 73: "staple book", 74: "counting money",
    75: "cutting nails", 76: "cutting paper (using scissors)", 77: "snapping fingers", 78: "open bottle",
    79: "sniff (smell)", 80: "squat down", 81: "toss a coin", 82: "fold paper", 83: "ball up paper",
    84: "play magic cube", 85: "apply cream on face", 86: "apply cream on hand back", 87: "put on bag",
    88: "take off bag", 89: "put something into a bag", 90: "take something out of a bag", 91: "open a box",
    92: "move heavy objects", 93: "shake fist", 94: "throw up cap/hat", 95: "hands up (both hands)", 96: "cross arms",
    97: "arm circles", 98: "arm swings", 99: "running on the spot", 100: "butt kicks (kick backward)",
    101: "cross toe touch", 102: "side kick", 103: "yawn", 104: "stretch oneself", 105: "blow nose",
    106: "hit other person with something", 107: "wield knife towards other person",
    108: "knock over other person (hit with body)", 109: "grab other person's stuff",
    110: "shoot at other person with a gun", 111: "step on foot", 112: "high-five", 113: "cheers and drink",
    114: "carry something with other person", 115: "take a photo of other person", 116: "follow other person",
    117: "whisper in other person's ear", 118: "exchange things with other person", 119: "support somebody with hand",
    120: "finger-guessing game (playing rock-paper-scissors)",
}

#: The two-person (mutual) actions, in ActFormer's label order.
MUTUAL_ACTIONS = tuple(range(50, 61)) + tuple(range(106, 121))
#: The one-person actions, in ActFormer's label order.
SINGLE_ACTIONS = tuple(a for a in range(1, 121) if a not in MUTUAL_ACTIONS)
SINGLE_CLASS_NAMES = tuple(ACTION_NAMES[a] for a in SINGLE_ACTIONS)
MUTUAL_CLASS_NAMES = tuple(ACTION_NAMES[a] for a in MUTUAL_ACTIONS)

#: Performers of the cross-subject training split (FACTS 1.3); the other 53 of the 106 are the test split.
XSUB_TRAIN_SUBJECTS = frozenset((
    1, 2, 4, 5, 8, 9, 13, 14, 15, 16, 17, 18, 19, 25, 27, 28, 31, 34, 35, 38, 45, 46, 47, 49, 50, 52, 53, 54, 55, 56,
    57, 58, 59, 70, 74, 78, 80, 81, 82, 83, 84, 85, 86, 89, 91, 92, 93, 94, 95, 97, 98, 100, 103,
))
NUM_SUBJECTS = 106
FPS = 30.0


# --- ActFormer's preparation of Kinect skeletons (AF:datasets/ntu120/prepare_ntu_data.py) --------------------

GapFill = Literal["code", "linear"]
#: ActFormer's temporal smoothing of every prepared skeleton (frames).
SMOOTHING_SIGMA = 3.0


def fill_missing(joints: np.ndarray, detected: np.ndarray, rule: GapFill = "code") -> np.ndarray:
    """One body's joints ``[T, J, 3]`` with its undetected frames filled, ``detected [T]`` bool (at least one).

    Before the first detection, the first detected skeleton; after the last, the last one. Between two
    detections at frames a < b with a gap, ``rule="code"`` does what ActFormer's code does: it means to
    interpolate linearly but writes only frame a + 1, so frames a + 2 .. b - 1 stay zero (the smoothing then
    blends them in); ``"linear"`` interpolates every frame of the gap, as the code intends.
    """
    detected = np.asarray(detected, bool)
    joints = np.asarray(joints, np.float64)
    if detected.shape != joints.shape[:1] or joints.ndim != 3:
        raise ValueError(f"detected: expected [T] = ({joints.shape[0]},) for joints [T, J, 3] = {joints.shape}, "
                         f"got {detected.shape}")
    if rule not in ("code", "linear"):
        raise ValueError(f"rule: expected 'code' or 'linear', got {rule!r}")
    frames = np.flatnonzero(detected)
    if frames.size == 0:
        raise ValueError("detected: the body is never detected; nothing to fill from")
    out = np.where(detected[:, None, None], joints, 0.0)
    out[: frames[0]] = joints[frames[0]]
    out[frames[-1] + 1:] = joints[frames[-1]]
    for a, b in zip(frames[:-1], frames[1:]):
        if b - a < 2:
            continue
        gap = np.arange(a + 1, b) if rule == "linear" else np.array([a + 1])
        w = ((gap - a) / (b - a))[:, None, None]
        out[gap] = w * joints[b] + (1.0 - w) * joints[a]
    return out


def gaussian_smooth(x: np.ndarray, sigma: float = SMOOTHING_SIGMA, axis: int = 0) -> np.ndarray:
    """A Gaussian filter along ``axis``, as ``scipy.ndimage.gaussian_filter1d`` (its defaults: kernel radius
    ``int(4 sigma + 0.5)``, edges mirrored including the edge sample), in numpy."""
    x = np.moveaxis(np.asarray(x, np.float64), axis, 0)
    radius = int(4.0 * sigma + 0.5)
    taps = np.exp(-0.5 * (np.arange(-radius, radius + 1) / sigma) ** 2)
    taps /= taps.sum()
    padded = x
    while padded.shape[0] < x.shape[0] + 2 * radius:  # a clip shorter than the kernel: mirror repeatedly
        need = x.shape[0] + 2 * radius - padded.shape[0]
        grow = min(need // 2 + 1, padded.shape[0])
        padded = np.concatenate([padded[:grow][::-1], padded, padded[-grow:][::-1]])
    start = (padded.shape[0] - x.shape[0]) // 2
    out = sum(w * padded[start - radius + k: start - radius + k + x.shape[0]] for k, w in enumerate(taps))
    return np.moveaxis(out, 0, axis)
