"""The league (docs/league.md): every ABS law of the registry tuned alike on each ABS plant, then
scored on held-out cases it was not tuned on. `cases` declares the plants, training roads and
held-out cases; `plan` turns them into a study (run, stored and resumed by `studies.runner`);
`score` simulates each tuned law on the held-out cases; `page` writes the ranked table and the
figures."""
