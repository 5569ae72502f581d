#!/usr/bin/env python3
"""Trains printlight's learned predictor (`--integrator learned`).

  scripts/train_learned.py [--build build] [--work /tmp/printlight-train]
      [--volumes 100] [--spp 16] [--seed 1] [--epochs 12]
      (--spp: samples per voxel on a volume of 60 mm^2; larger ones get fewer)
      [--materials data/materials/resins_illustrative.json]

1. make-test-data --training writes procedural label volumes (cuboids with
   layered, regioned, striped and dotted halftones over a core).
2. printlight renders each (lighttrace, surface-voxel sensor with patches)
   and `printlight learned-data` turns the render into rows: one channel's
   label descriptor and the voxel's response with its standard error.
   Noisy targets are fine: the squared loss converges to their mean.
3. A small perceptron is trained with python3-torch (Debian's 1.13), the
   volumes split by volume into training and validation, and written as
   JSON beside the material table (MATERIALS.learned.json): weights, what
   it was trained for, and its error bound from the validation volumes.
Everything follows from --seed: the volumes, the renders and the training
(torch's deterministic CPU kernels, one thread).
"""
import argparse
import json
import os
import re
import subprocess
import sys

import numpy as np


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def make_rows(args):
    os.makedirs(args.work, exist_ok=True)
    run([f"{args.build}/make-test-data", "--training", str(args.volumes), str(args.seed), args.work])
    files = []
    for i in range(args.volumes):
        name = f"train_{i:03d}"
        rows = os.path.join(args.work, name + ".npy")
        files.append(rows)
        if os.path.exists(rows):
            continue
        scene = os.path.join(args.work, name + "_surface.json")
        with open(scene, "w") as f:
            json.dump({
                "object": {"mesh": name + ".gltf", "labels": name + ".vdb",
                           "materials": os.path.abspath(args.materials), "ior": 1.5},
                "environment": {"radiance": [1, 1, 1]},
                "sensor": {"type": "surface_voxels", "footprint": "patch"},
                "render": {"integrator": "lighttrace", "spp": args.spp, "seed": args.seed + i,
                           "channel": "rgb", "reentry": False},
                "output": {"path": name + "_render"}}, f, indent=1)
        # Samples per voxel fall with the surface's area: every volume gets
        # about the same number of paths (noisy targets average out).
        info = subprocess.run([f"{args.build}/printlight", "info", os.path.join(args.work, name + ".vdb")],
                              check=True, capture_output=True, text=True).stdout
        x, y, z = (float(v) for v in re.search(r"\(([\d.]+) x ([\d.]+) x ([\d.]+) mm\)", info).groups())
        area_mm2 = 2 * (x * y + y * z + z * x)
        spp = max(2, round(args.spp * 60.0 / area_mm2))
        with open(scene) as f:
            described = json.load(f)
        described["render"]["spp"] = spp
        with open(scene, "w") as f:
            json.dump(described, f, indent=1)
        render = os.path.join(args.work, name + "_render")
        run([f"{args.build}/printlight", "render", scene, "-o", render])
        run([f"{args.build}/printlight", "learned-data", scene, "--reference", render + ".exr", "-o", rows])
        print(f"train_learned: {name} ({x:.1f} x {y:.1f} x {z:.1f} mm) rendered at {spp} spp", flush=True)
    return files


def voxel_size(args):
    info = subprocess.run([f"{args.build}/printlight", "info", os.path.join(args.work, "train_000.vdb")],
                          check=True, capture_output=True, text=True).stdout
    m = re.search(r"voxel size:\s+([\d.]+) x ([\d.]+) x ([\d.]+) mm", info)
    return [float(m.group(k)) for k in (1, 2, 3)]


def train(args, files):
    import torch
    torch.manual_seed(args.seed)
    torch.set_num_threads(1)
    torch.use_deterministic_algorithms(True)
    # At most --rows-per-volume rows from each volume (every k-th: its
    # neighbours say much the same), so that large volumes do not dominate.
    tables = []
    for f in files:
        rows = np.load(f, mmap_mode="r")
        step = -(-len(rows) // args.rows_per_volume)
        tables.append(np.array(rows[::step]))
    validation_count = max(1, len(tables) // 8)
    train_rows = np.concatenate(tables[:-validation_count])
    valid_rows = np.concatenate(tables[-validation_count:])
    width = train_rows.shape[1] - 4
    x = torch.from_numpy(train_rows[:, :width].copy())
    y = torch.from_numpy(train_rows[:, width].copy())
    mean, std = x.mean(0), x.std(0).clamp(min=1e-3)
    hidden = args.hidden
    net = torch.nn.Sequential(torch.nn.Linear(width, hidden), torch.nn.ReLU(),
                              torch.nn.Linear(hidden, hidden), torch.nn.ReLU(),
                              torch.nn.Linear(hidden, 1))
    optimiser = torch.optim.Adam(net.parameters(), lr=2e-3)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, T_max=args.epochs)
    generator = torch.Generator().manual_seed(args.seed)
    xn = (x - mean) / std
    vx = (torch.from_numpy(valid_rows[:, :width].copy()) - mean) / std
    vy = torch.from_numpy(valid_rows[:, width].copy())
    vse = torch.from_numpy(valid_rows[:, width + 1].copy())
    for epoch in range(args.epochs):
        order = torch.randperm(len(xn), generator=generator)
        total = 0.0
        for k in range(0, len(order), args.batch):
            idx = order[k:k + args.batch]
            loss = torch.mean((net(xn[idx]).squeeze(1) - y[idx]) ** 2)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            total += float(loss) * len(idx)
        schedule.step()
        with torch.no_grad():
            pv = net(vx).squeeze(1)
            # The validation targets' own noise is part of the squared error: take it out.
            bias2 = float(torch.mean((pv - vy) ** 2) - torch.mean(vse ** 2))
        print(f"train_learned: epoch {epoch + 1}: training mse {total / len(xn):.3e}, "
              f"validation rms error net of noise {np.sqrt(max(bias2, 0)):.4f}", flush=True)
    with torch.no_grad():
        pv = net(vx).squeeze(1).clamp(min=0).numpy()
    vy, vse = vy.numpy(), vse.numpy()
    # The bound share * R + floor: the smallest share (floor fixed at the
    # targets' scale) such that 95 % of validation rows lie within
    # 2 x hypot(bound, target error), as for a normal error.
    floor = 0.005
    share = 0.0
    for share in np.arange(0.0, 1.0, 0.005):
        bound = share * pv + floor
        if np.mean(np.abs(pv - vy) <= 2 * np.hypot(bound, vse)) >= 0.95:
            break
    # Fold the input normalisation into the first layer.
    layers = []
    linears = [m for m in net if isinstance(m, torch.nn.Linear)]
    for i, lin in enumerate(linears):
        w = lin.weight.detach().double()
        b = lin.bias.detach().double()
        if i == 0:
            b = b - w @ (mean.double() / std.double())
            w = w / std.double()
        layers.append({"inputs": int(w.shape[1]), "outputs": int(w.shape[0]),
                       "weights": [float(v) for v in w.reshape(-1).float()],
                       "bias": [float(v) for v in b.float()]})
    with open(args.materials) as f:
        materials = json.load(f)
    model = {
        "format": "printlight-learned-1",
        "comment": "Made by scripts/train_learned.py; do not edit. Valid only for these materials and voxels.",
        "trained_for": {"materials": {"materials": materials["materials"] if isinstance(materials, dict) else materials},
                        "voxel_size_mm": voxel_size(args)},
        "descriptor_size": width,
        "layers": layers,
        "error_bound": {"share": round(float(share), 4), "floor": floor},
        "training": {"seed": args.seed, "volumes": args.volumes, "spp": args.spp, "epochs": args.epochs,
                     "hidden": hidden, "training_rows": int(len(train_rows)),
                     "validation_rows": int(len(valid_rows)),
                     "validation_rms_error": float(np.sqrt(np.mean((pv - vy) ** 2))),
                     "validation_target_rms_noise": float(np.sqrt(np.mean(vse ** 2)))},
    }
    out = args.out or re.sub(r"\.json$", "", args.materials) + ".learned.json"
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(model, f, separators=(",", ":"))
    os.replace(tmp, out)
    print(f"train_learned: wrote {out} ({os.path.getsize(out)} bytes); error bound {share:.3f} R + {floor}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default="build")
    p.add_argument("--work", default="/tmp/printlight-train")
    p.add_argument("--materials", default="data/materials/resins_illustrative.json")
    p.add_argument("--out", default="")
    p.add_argument("--volumes", type=int, default=100)
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--epochs", type=int, default=12)
    p.add_argument("--hidden", type=int, default=64)
    p.add_argument("--batch", type=int, default=4096)
    p.add_argument("--rows-per-volume", type=int, default=90000)
    p.add_argument("--rows-only", action="store_true", help="make the training rows and stop")
    args = p.parse_args()
    files = make_rows(args)
    if not args.rows_only:
        train(args, files)


if __name__ == "__main__":
    sys.exit(main())
