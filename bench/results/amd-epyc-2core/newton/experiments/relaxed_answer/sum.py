import csv,sys
for tag in sys.argv[1:]:
  for name in ['rock','bp','hard','chain','log','large']:
    try: r=list(csv.DictReader(open(f'/tmp/scenes/{tag}_{name}.csv')))
    except Exception: continue
    f=sorted(float(x['factorizations']) for x in r); s=[float(x['solve_ms']) for x in r]
    last=sorted(s[-100:])
    print(f"{tag:6} {name:6} unsettled {sum(float(x['unsettled'])>0 for x in r):4d} solve {sum(s)/1000:6.1f} s slowest {max(s):6.0f} ms med-last100 {last[len(last)//2]:6.1f} ms fact med {f[len(f)//2]:4.0f} max {f[-1]:5.0f} KE {float(r[-1]['kinetic_energy']):.2e} pen {1000*max(float(x['max_penetration']) for x in r):.1f} mm worst {max(float(x['blcp_residual']) for x in r):.2e}")
