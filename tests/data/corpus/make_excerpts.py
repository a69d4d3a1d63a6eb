"""How the corpus's excerpts were cut (kept for the record; the tests read the .bvh files).

    python tests/data/corpus/make_excerpts.py SOURCE_DIR

SOURCE_DIR holds the original takes: Tencent-RoboticsX/lifelike-agility-and-play,
data/raw_mocap_data/*.bvh at commit cc9eaa9 (dog), the CMU clips of
shared/reference/motion (human), yuki-koyama/bvh11's resources/131_01.bvh (CMU's
3ds Max-friendly BVH conversion), and HDM05 takes (Acclaim ASF/AMC, converted to BVH by
``acclaim_to_bvh.py`` here, centimetres: ``python acclaim_to_bvh.py HDM_dg.asf
HDM_dg_06-03_03_120.amc HDM_dg_06-03_03_120.bvh 5.6444``). Each excerpt keeps the frames [first, last) of its
take at the take's own rate, and of the take's hierarchy only the joints that lead to
the feet (root, spine, legs, paws and what hangs below the paws: ears, tail, armour and
fingers are dropped; nothing a kept joint's position depends on is), numbers rounded to
two decimals (the takes' units are centimetres or CMU units and degrees).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[3]))

from app.analysis.bvh import BvhClip, read_bvh

DOG_FEET = ("b__LeftFinger", "b_RightFinger", "b_LeftToe", "b_RightToe")
HUMAN_FEET = ("LeftToeBase", "RightToeBase", "LeftHand", "RightHand")
MAX_FEET = ("LeftToe", "RightToe", "LeftWrist", "RightWrist")  # the 3ds Max-friendly conversion's names
HDM_FEET = ("ltoes", "rtoes", "lhand", "rhand")  # HDM05's (Acclaim) names

# name: (source take, first frame, last frame, the joints to keep with what leads to them)
EXCERPTS: dict[str, tuple[str, int, int, tuple[str, ...]]] = {
    "dog_walk_tencent_walkrun001_f200-560": ("dog_quad_walkrun_001", 200, 560, DOG_FEET),
    "dog_walk_tencent_walkrun005_f200-560": ("dog_quad_walkrun_005", 200, 560, DOG_FEET),
    "dog_backwards_tencent_back001_f330-730": ("dog_back_001", 330, 730, DOG_FEET),
    "dog_trot_tencent_walkrun006_f480-660": ("dog_quad_walkrun_006", 480, 660, DOG_FEET),
    "dog_trot_tencent_walkrun007_f440-580": ("dog_quad_walkrun_007", 440, 580, DOG_FEET),
    "dog_walk_tencent_walkrun006_f360-520": ("dog_quad_walkrun_006", 360, 520, DOG_FEET),
    "dog_walk_tencent_walkrun007_f150-330": ("dog_quad_walkrun_007", 150, 330, DOG_FEET),
    "dog_gallop_tencent_walkrun005_f590-710": ("dog_quad_walkrun_005", 590, 710, DOG_FEET),
    "dog_gallop_tencent_walkrun006_f690-810": ("dog_quad_walkrun_006", 690, 810, DOG_FEET),
    "dog_gallop_tencent_walkrun007_f560-680": ("dog_quad_walkrun_007", 560, 680, DOG_FEET),
    "dog_stand_walk_tencent_walkrun005_f0-420": ("dog_quad_walkrun_005", 0, 420, DOG_FEET),
    "human_walk_cmu_12_01_f1-524": ("human_walk_cmu_12_01", 1, 524, HUMAN_FEET),
    "human_run_cmu_09_01_f1-149": ("human_run_cmu_09_01", 1, 149, HUMAN_FEET),
    "human_walk_loop_cmu_12_01_f101-251": ("human_walk_cmu_12_01", 101, 251, HUMAN_FEET),  # one cycle, as a loop
    "human_start_walk_stop_cmu_131_01_max": ("131_01", 0, 994, MAX_FEET),
    "human_jog_hdm05_dg_06-03_03": ("HDM_dg_06-03_03_120", 0, 202, HDM_FEET),
    "human_jog_circle_hdm05_bd_001": ("HDM_bd_jogLeftCircle4StepsRstart_001_120", 0, 244, HDM_FEET),
    "human_jog_circle_hdm05_bk_005": ("HDM_bk_jogLeftCircle4StepsRstart_005_120", 0, 274, HDM_FEET),
    "human_jog_circle_hdm05_dg_009": ("HDM_dg_jogLeftCircle4StepsRstart_009_120", 0, 200, HDM_FEET),
    "human_jog_circle_hdm05_mm_011": ("HDM_mm_jogLeftCircle4StepsRstart_011_120", 0, 224, HDM_FEET),
    "human_jog_circle_hdm05_tr_015": ("HDM_tr_jogLeftCircle4StepsRstart_015_120", 0, 262, HDM_FEET),
    "human_jog_circle_hdm05_tr_017": ("HDM_tr_jogLeftCircle4StepsRstart_017_120", 0, 253, HDM_FEET),
}


def _kept(clip: BvhClip, wanted: tuple[str, ...]) -> list[int]:
    """Indices of the joints ``wanted``, their ancestors and their descendants."""
    roots = {clip.index(name) for name in wanted}
    keep: set[int] = set()
    for i in range(len(clip.joints)):
        chain = [i] + _ancestors(clip, i)
        if i in roots or roots & set(chain):  # a wanted joint or below one
            keep.add(i)
    for i in roots:
        keep.update([i] + _ancestors(clip, i))
    return sorted(keep)


def _ancestors(clip: BvhClip, i: int) -> list[int]:
    out = []
    while clip.joints[i].parent >= 0:
        i = clip.joints[i].parent
        out.append(i)
    return out


def excerpt(source: Path, first: int, last: int, wanted: tuple[str, ...], drop: tuple[str, ...] = ()) -> str:
    """The BVH text of frames [first, last) of ``source`` with only the joints that lead
    to ``wanted`` and hang below them, less the joints ``drop`` and what hangs below those."""
    clip = read_bvh(source)
    dropped = {clip.index(name) for name in drop}
    keep = [i for i in _kept(clip, wanted) if not dropped & ({i} | set(_ancestors(clip, i)))]
    children: dict[int, list[int]] = {i: [] for i in keep}
    for i in keep:
        if clip.joints[i].parent >= 0:
            children[clip.joints[i].parent].append(i)
    lines: list[str] = ["HIERARCHY"]
    columns: list[int] = []

    def write(i: int, depth: int) -> None:
        joint, pad = clip.joints[i], "  " * depth
        if joint.end_site:
            lines.extend([f"{pad}End Site", f"{pad}{{", f"{pad}  OFFSET " + " ".join(f"{v:.4f}" for v in joint.offset),
                          f"{pad}}}"])
            return
        lines.extend([f"{pad}{'ROOT' if joint.parent < 0 else 'JOINT'} {joint.name}", f"{pad}{{",
                      f"{pad}  OFFSET " + " ".join(f"{v:.4f}" for v in joint.offset),
                      f"{pad}  CHANNELS {len(joint.channels)} " + " ".join(joint.channels)])
        columns.extend(range(joint.first_channel, joint.first_channel + len(joint.channels)))
        for c in children[i]:
            write(c, depth + 1)
        if not children[i]:  # a joint whose children were all dropped ends in a site at itself
            lines.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET 0.0000 0.0000 0.0000", f"{pad}  }}"])
        lines.append(f"{pad}}}")

    write(keep[0], 0)
    data = clip.frames[first:last][:, columns]
    lines += ["MOTION", f"Frames: {len(data)}", f"Frame Time: {clip.frame_time:.7f}"]
    lines += [" ".join(f"{v:.2f}" for v in row) for row in data]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    source_dir, out = Path(sys.argv[1]), Path(__file__).parent
    for name, (take, first, last, wanted) in EXCERPTS.items():
        (out / f"{name}.bvh").write_text(excerpt(source_dir / f"{take}.bvh", first, last, wanted))
        print(name)
