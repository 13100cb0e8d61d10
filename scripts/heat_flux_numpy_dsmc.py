#!/usr/bin/python3
"""An independent 40-line DSMC of paper 001's Eq. 3.1 at alpha = 1 (elastic hard spheres), written
without any gdsmc code, to cross-check gdsmc's kappa'/kappa0 (docs/validation/heat-flux.md,
findings). Vectorised: each step draws Poisson(N(N-1)/2 pi w dt / V) candidate pairs as disjoint
pairs of a random permutation, accepts with |g|/w, scatters with sigma_hat from Theta(g.s)(g.s),
applies Eq. 4.1 and the thermostat Eq. 4.2, and averages b'_1 (Eq. 3.10) over t in [10, 25] tau.
Units m = 1, T = 1, sigma = 1. Usage: heat_flux_numpy_dsmc.py SEED EPS_STAR  (prints b'_1, kappa'/kappa0)."""
import numpy as np, sys
rng=np.random.default_rng(int(sys.argv[1]))
N=100000; n=1e-3; lam=1/(np.sqrt(2)*np.pi*n); v0=np.sqrt(2.0); tau=lam/v0
eps_star=float(sys.argv[2]); eps=eps_star/lam; dt=0.03*tau; V=N/n
v=rng.normal(size=(N,3))
w=6.0*np.sqrt(2.0)  # majorant of |g|
b1s=[]
for step in range(int(25/0.03)):
    # collisions: expected candidates N(N-1)/2 * pi * w * dt / V, drawn as disjoint pairs
    K=rng.poisson(0.5*N*(N-1)*np.pi*w*dt/V)
    K=min(K,N//2)
    p=rng.permutation(N)[:2*K]; i=p[:K]; j=p[K:]
    g=v[i]-v[j]; gn=np.linalg.norm(g,axis=1)
    acc=rng.random(K)*w<gn
    i,j,g,gn=i[acc],j[acc],g[acc],gn[acc]
    u=rng.normal(size=(len(i),3)); u/=np.linalg.norm(u,axis=1)[:,None]
    s=g/gn[:,None]+u; s/=np.linalg.norm(s,axis=1)[:,None]
    gs=np.sum(g*s,axis=1)[:,None]
    v[i]-=gs*s; v[j]+=gs*s
    # force, Eq. 4.1
    vx=v[:,0].copy()
    v-=0.5*v*vx[:,None]*eps*dt
    # thermostat Eq. 4.2
    v-=v.mean(0); v*=np.sqrt(3*N/np.sum(v*v))
    t=(step+1)*0.03
    if t>=10 and step%2==0:
        c=v/v0; c2=np.sum(c*c,1)
        b1s.append(0.8*np.mean(c[:,0]*(2.5-c2))/eps_star)
b=np.mean(b1s)
print(b, b*16/(15*np.sqrt(np.pi)))
