# A/B of the LRP bench at 2 threads: old (/tmp/wt) and new (/work/main) alternating
for i in 1 2; do
for b in /tmp/wt/build/rbpart /work/main/build/rbpart; do
  tag=$(echo $b | cut -d/ -f2-3 | tr / _)_$i
  rm -rf /tmp/s27/bench_$tag
  $b bench --preset paper --scenes large_rock_pile --partitioners metis --refine none --nmax 300 --threads 2 --no-scaling --no-reference --every 10 --out /tmp/s27/bench_$tag > /tmp/s27/bench_$tag.log 2>&1
  echo $tag; grep -iE "metis|direct" /tmp/s27/bench_$tag/table1.md | head -4
done; done
