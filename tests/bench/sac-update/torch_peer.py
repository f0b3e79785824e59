#!/usr/bin/python3
"""The PyTorch peer of the sac-update bench: the same SAC update as learner/sac.cc on the same
networks (common/rl/networks.h) and the very batch the C++ bench sampled, timed the same way
(median of repeats after one warm-up). Sizes and SAC settings come from spec.json, which the
C++ bench writes from the config; nothing is set here but the thread count.

  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 torch_peer.py DIR --threads 1

prints a table and, as its last line, one JSON object with torch_ms_batch<B> for every
DIR/batch<B>.bin, and the single-thread sgemm rate of torch.mm and numpy at 2048^3.
"""

import argparse
import glob
import json
import math
import os
import re
import time

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F


def load_batch(path):
    with open(path, "rb") as f:
        B, N, D, G, A = np.frombuffer(f.read(20), dtype=np.int32)
        rest = np.frombuffer(f.read(), dtype=np.float32)
    sizes = [B * N * D, B * N * D, B * N, B * G, B * A, B, B]
    parts, at = [], 0
    for s in sizes:
        parts.append(torch.from_numpy(rest[at:at + s].copy()))
        at += s
    assert at == rest.size, "batch file size does not match its header"
    ent, nxt, mask, goal, act, rew, boot = parts
    return dict(entities=ent.view(B * N, D), next_entities=nxt.view(B * N, D), mask=mask.view(B, N),
                goals=goal.view(B, G), actions=act.view(B, A), rewards=rew.view(B, 1), boot=boot.view(B, 1),
                B=int(B), N=int(N))


def xavier_linear(i, o, bias=True):
    # Xavier uniform, zero bias: as nn::Linear (the initialisation does not change the timing)
    layer = nn.Linear(i, o, bias=bias)
    nn.init.xavier_uniform_(layer.weight)
    if bias:
        nn.init.zeros_(layer.bias)
    return layer


class GoalAttention(nn.Module):
    """entity tokens -> Linear(E) -> key, value (Linear(E, E) each); goal token -> Linear(E, no
    bias) = goal embedding -> query (Linear(E, E)); heads of E/heads over the valid entities,
    scaled by 1/sqrt(head size); output projection Linear(E, E). As nn::GoalAttention."""

    def __init__(self, s):
        super().__init__()
        E = s["embed_dim"]
        self.heads = s["heads"]
        self.entity = xavier_linear(s["entity_dim"], E)
        self.goal = xavier_linear(s["goal_dim"], E, bias=False)
        self.query = xavier_linear(E, E)
        self.key = xavier_linear(E, E)
        self.value = xavier_linear(E, E)
        self.out = xavier_linear(E, E)

    def forward(self, entities, mask, goals):
        B, N = mask.shape
        H = self.heads
        tok = self.entity(entities)
        k = self.key(tok).view(B, N, H, -1).transpose(1, 2)          # B H N dh
        v = self.value(tok).view(B, N, H, -1).transpose(1, 2)        # B H N dh
        ge = self.goal(goals)
        q = self.query(ge).view(B, H, 1, -1)                         # B H 1 dh
        scores = torch.matmul(q, k.transpose(-1, -2)) / math.sqrt(q.shape[-1])  # B H 1 N
        scores = scores.masked_fill(mask.view(B, 1, 1, N) == 0, float("-inf"))
        w = torch.softmax(scores, dim=-1)
        heads = torch.matmul(w, v).view(B, -1)                       # B E (head-major, as the tape)
        return self.out(heads), ge


def mlp(i, hidden, o):
    layers, prev = [], i
    for h in hidden:
        layers += [xavier_linear(prev, h), nn.ReLU()]
        prev = h
    layers.append(xavier_linear(prev, o))
    return nn.Sequential(*layers)


class Policy(nn.Module):
    def __init__(self, s):
        super().__init__()
        self.att = GoalAttention(s)
        self.mlp = mlp(2 * s["embed_dim"], s["policy_hidden"], 2 * s["action_dim"])
        self.A = s["action_dim"]
        self.lo, self.hi = s["log_std_min"], s["log_std_max"]

    def forward(self, entities, mask, goals, eps):
        att, ge = self.att(entities, mask, goals)
        out = self.mlp(torch.cat([att, ge], 1))
        mean, log_std = out[:, :self.A], out[:, self.A:].clamp(self.lo, self.hi)
        u = mean + log_std.exp() * eps
        action = torch.tanh(u)
        # gaussian density of u, then the tanh correction log(1 - tanh(u)^2) in its stable form
        log_prob = (-0.5 * eps.pow(2) - 0.5 * math.log(2 * math.pi) - log_std
                    + 2 * (u + F.softplus(-2 * u) - math.log(2))).sum(1, keepdim=True)
        return action, log_prob


class Critic(nn.Module):
    def __init__(self, s):
        super().__init__()
        self.att = GoalAttention(s)
        self.mlp = mlp(2 * s["embed_dim"] + s["action_dim"], s["q_hidden"], 1)

    def forward(self, entities, mask, goals, actions):
        att, ge = self.att(entities, mask, goals)
        return self.mlp(torch.cat([att, ge, actions], 1))


class Sac:
    def __init__(self, s):
        self.s = s
        self.policy = Policy(s)
        self.q1, self.q2 = Critic(s), Critic(s)
        self.q1_target, self.q2_target = Critic(s), Critic(s)
        self.q1_target.load_state_dict(self.q1.state_dict())
        self.q2_target.load_state_dict(self.q2.state_dict())
        for p in list(self.q1_target.parameters()) + list(self.q2_target.parameters()):
            p.requires_grad_(False)
        self.log_alpha = torch.tensor([math.log(s["initial_alpha"])], requires_grad=True)
        self.q_params = list(self.q1.parameters()) + list(self.q2.parameters())
        self.policy_opt = torch.optim.Adam(self.policy.parameters(), lr=s["policy_lr"])
        self.q_opt = torch.optim.Adam(self.q_params, lr=s["q_lr"])
        self.alpha_opt = torch.optim.Adam([self.log_alpha], lr=s["alpha_lr"])
        self.target_params = list(self.q1_target.parameters()) + list(self.q2_target.parameters())

    def update(self, b):
        s = self.s
        B, A = b["B"], s["action_dim"]
        alpha = self.log_alpha.detach().exp()
        with torch.no_grad():
            next_a, next_logp = self.policy(b["next_entities"], b["mask"], b["goals"], torch.randn(B, A))
            t = torch.min(self.q1_target(b["next_entities"], b["mask"], b["goals"], next_a),
                          self.q2_target(b["next_entities"], b["mask"], b["goals"], next_a))
            y = s["reward_scale"] * b["rewards"] + s["discount"] * b["boot"] * (t - alpha * next_logp)
        # critics
        q1 = self.q1(b["entities"], b["mask"], b["goals"], b["actions"])
        q2 = self.q2(b["entities"], b["mask"], b["goals"], b["actions"])
        q_loss = F.mse_loss(q1, y) + F.mse_loss(q2, y)
        self.q_opt.zero_grad(set_to_none=True)
        q_loss.backward()
        if s["grad_clip_norm"] > 0:
            nn.utils.clip_grad_norm_(self.q_params, s["grad_clip_norm"])
        self.q_opt.step()
        # policy, critics frozen (no weight gradients computed for them, as the tape)
        for p in self.q_params:
            p.requires_grad_(False)
        a, logp = self.policy(b["entities"], b["mask"], b["goals"], torch.randn(B, A))
        qmin = torch.min(self.q1(b["entities"], b["mask"], b["goals"], a),
                         self.q2(b["entities"], b["mask"], b["goals"], a))
        p_loss = (alpha * logp - qmin).mean()
        self.policy_opt.zero_grad(set_to_none=True)
        p_loss.backward()
        if s["grad_clip_norm"] > 0:
            nn.utils.clip_grad_norm_(self.policy.parameters(), s["grad_clip_norm"])
        self.policy_opt.step()
        for p in self.q_params:
            p.requires_grad_(True)
        # temperature
        if s["auto_entropy"]:
            a_loss = -(self.log_alpha * (logp.detach().mean() + s["target_entropy"]))
            self.alpha_opt.zero_grad(set_to_none=True)
            a_loss.backward()
            self.alpha_opt.step()
        # soft target update
        with torch.no_grad():
            torch._foreach_mul_(self.target_params, 1 - s["tau"])
            torch._foreach_add_(self.target_params, self.q_params, alpha=s["tau"])
        return q_loss.item(), p_loss.item()


def median_ms(repeats, f):
    """median wall ms after a warm-up; and the process CPU ms per call over the same calls"""
    cpu0 = time.process_time()
    f()
    t = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        t.append((time.perf_counter() - start) * 1e3)
    cpu_ms = (time.process_time() - cpu0) * 1e3 / (repeats + 1)
    t.sort()
    return t[len(t) // 2], cpu_ms


def sgemm_gflops(mm, a, b):
    """best of 5 by wall time and by process CPU time (one thread: CPU time is the work)"""
    best, best_cpu = 1e30, 1e30
    mm(a, b)
    for _ in range(5):
        cpu0 = time.process_time()
        start = time.perf_counter()
        mm(a, b)
        best = min(best, time.perf_counter() - start)
        best_cpu = min(best_cpu, time.process_time() - cpu0)
    flop = 2.0 * a.shape[0] ** 3
    return flop / best * 1e-9, flop / best_cpu * 1e-9


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.set_num_interop_threads(args.threads)
    torch.manual_seed(1)
    with open(os.path.join(args.dir, "spec.json")) as f:
        spec = json.load(f)
    result = {"torch_version": torch.__version__, "torch_threads": torch.get_num_threads(),
              "openblas_threads": os.environ.get("OPENBLAS_NUM_THREADS", ""),
              "omp_threads": os.environ.get("OMP_NUM_THREADS", "")}
    print(f"PyTorch {torch.__version__}, {torch.get_num_threads()} thread(s) "
          f"(OMP_NUM_THREADS={result['omp_threads']}, OPENBLAS_NUM_THREADS={result['openblas_threads']})")
    print(f"{'batch':<8}{'torch ms':>10}{'cpu ms':>10}{'q loss':>12}")
    files = sorted(glob.glob(os.path.join(args.dir, "batch*.bin")),
                   key=lambda p: -int(re.search(r"batch(\d+)", p).group(1)))
    for path in files:
        b = load_batch(path)
        agent = Sac(spec)
        losses = []
        ms, cpu_ms = median_ms(11 if b["B"] >= 1024 else 41, lambda: losses.append(agent.update(b)))
        assert all(math.isfinite(q) and math.isfinite(p) for q, p in losses), "non-finite losses"
        result[f"torch_ms_batch{b['B']}"] = round(ms, 3)
        result[f"torch_cpu_ms_batch{b['B']}"] = round(cpu_ms, 3)
        print(f"{b['B']:<8}{ms:>10.2f}{cpu_ms:>10.2f}{losses[-1][0]:>12.4f}")
    n = 2048
    a32 = torch.rand(n, n)
    b32 = torch.rand(n, n)
    na, nb = a32.numpy(), b32.numpy()
    for name, mm, x, y in (("torch", torch.mm, a32, b32), ("numpy", np.matmul, na, nb)):
        wall, cpu = sgemm_gflops(mm, x, y)
        result[f"{name}_sgemm_gflops"] = round(wall, 2)
        result[f"{name}_sgemm_gflops_cpu"] = round(cpu, 2)
    print(f"sgemm 2048^3 (wall / CPU time): torch.mm {result['torch_sgemm_gflops']:.1f} / "
          f"{result['torch_sgemm_gflops_cpu']:.1f} GFLOP/s, numpy {result['numpy_sgemm_gflops']:.1f} / "
          f"{result['numpy_sgemm_gflops_cpu']:.1f} GFLOP/s")
    print(json.dumps(result))


if __name__ == "__main__":
    main()
