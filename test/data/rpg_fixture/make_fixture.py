# Writes test/data/rpg_fixture: a 6-DoF ground truth and estimate (TUM), and the values
# rpg_trajectory_evaluation's own functions give on them (expected.json), for test_metrics_6dof.
# Usage: python3 make_fixture.py RPG_CHECKOUT   (uzh-rpg/rpg_trajectory_evaluation, commit 8c8ceec55c5c5094a6494208cfc5f54afe0bbc4d,
# with numpy; its code is run unchanged and not part of this project).
import json, os, sys
import numpy as np
sys.path.insert(0, os.path.join(sys.argv[1], 'src', 'rpg_trajectory_evaluation'))
OUT = os.path.dirname(os.path.abspath(__file__))
import transformations as tf
import align_utils as au
import compute_trajectory_errors as te
import trajectory_utils as tu
import results_writer as rw

rng = np.random.RandomState(7)
n = 500
t = np.arange(n) * 0.25
# a hand-held walk round a loop with stairs: ~1.3 m/s, yaw turning, roll/pitch wobble, z going up and down
s = 1.3 * t
yaw = 2 * np.pi * s / s[-1] * 1.0 + 0.1 * np.sin(0.7 * t)
x = np.cumsum(1.3 * 0.25 * np.cos(yaw)); y = np.cumsum(1.3 * 0.25 * np.sin(yaw))
z = 1.2 + 1.5 * np.sin(np.pi * s / s[-1]) ** 2 + 0.03 * np.sin(9 * t)
roll = 0.05 * np.sin(5.5 * t); pitch = 0.06 * np.sin(3.7 * t + 1)
def quat(r, p, yw):
    return tf.quaternion_from_euler(yw, p, r, 'rzyx')  # rpg's transformations.py: x, y, z, w (as TUM)
gt = []
for i in range(n):
    q = quat(roll[i], pitch[i], yaw[i])
    gt.append([t[i], x[i], y[i], z[i], q[0], q[1], q[2], q[3]])
gt = np.array(gt)
# the estimate: a yaw drift, a slow roll bias, 2 % scale, noise, in another world frame
est = []
dyaw = np.cumsum(rng.normal(0, 0.002, n)) + 0.0004 * np.arange(n)
droll = 0.01 * np.arange(n) / n
pos = np.zeros(3); prev = None
Rw = tf.euler_matrix(0.3, -0.02, 0.01, 'rzyx')[:3, :3]; tw = np.array([5.0, -3.0, 0.5])
for i in range(n):
    step = np.zeros(3) if i == 0 else (gt[i, 1:4] - gt[i - 1, 1:4]) * 1.02
    Rd = tf.euler_matrix(dyaw[i], 0.0, droll[i], 'rzyx')[:3, :3]
    pos = pos + Rd.dot(step) + rng.normal(0, 0.01, 3)
    Rgt = tf.quaternion_matrix(gt[i, 4:8])[:3, :3]
    R = Rw.dot(Rd).dot(Rgt)
    p = Rw.dot(pos + gt[0, 1:4]) + tw
    M = np.eye(4); M[:3, :3] = R
    q = tf.quaternion_from_matrix(M)
    est.append([t[i], p[0], p[1], p[2], q[0], q[1], q[2], q[3]])
est = np.array(est)
np.savetxt(os.path.join(OUT, 'gt.txt'), gt, fmt='%.9f')
np.savetxt(os.path.join(OUT, 'est.txt'), est, fmt='%.9f')
# read back as written (9 decimals), as the C++ side reads them
gt = np.loadtxt(os.path.join(OUT, 'gt.txt')); est = np.loadtxt(os.path.join(OUT, 'est.txt'))
p_gt, q_gt = gt[:, 1:4], gt[:, 4:8]  # as rpg's trajectory_loading reads TUM: qx qy qz qw
p_es, q_es = est[:, 1:4], est[:, 4:8]
out = {}
for kind in ['se3', 'posyaw']:
    s_, R, tt = au.alignTrajectory(p_es, p_gt, q_es, q_gt, kind, -1)
    p_al = np.array([s_ * R.dot(p) + tt for p in p_es])
    q_al = []
    for q in q_es:
        M = tf.quaternion_matrix(q); M[:3, :3] = R.dot(M[:3, :3]); q_al.append(tf.quaternion_from_matrix(M))
    e_trans, _, e_rot, _, _ = te.compute_absolute_error(p_al, np.array(q_al), p_gt, q_gt)
    out['ate_' + kind] = {'rmse_m': rw.compute_statistics(e_trans)['rmse'], 'rot_rmse_deg': rw.compute_statistics(e_rot)['rmse']}
acc = tu.get_distance_from_start(p_gt)
out['length_m'] = float(acc[-1])
re = []
for d in [10.0, 20.0, 50.0, 100.0]:
    errs, tn, tp, yw, grav, rot, _ = te.compute_relative_error(p_es, q_es, p_gt, q_gt, np.eye(4), d, 0.2 * d, acc)
    st = rw.compute_statistics(tn)
    re.append({'distance_m': d, 'samples': len(tn), 'trans_mean_m': st['mean'], 'trans_median_m': st['median'],
               'trans_rmse_m': st['rmse'], 'trans_mean_pct': float(np.mean(tp)), 'yaw_mean_deg': float(np.mean(yw)),
               'gravity_mean_deg': float(np.mean(grav)), 'rot_mean_deg': float(np.mean(rot))})
out['re'] = re
R, tt = au.alignPositionYawSingle(p_es, p_gt, q_es, q_gt)
fin = np.linalg.norm(R.dot(p_es[-1]) + tt - p_gt[-1])
out['final'] = {'final_m': float(fin), 'final_pct': float(100 * fin / acc[-1]), 'distance_m': float(acc[-1])}
json.dump(out, open(os.path.join(OUT, 'expected.json'), 'w'), indent=1)
print(json.dumps(out, indent=1)[:1500])
