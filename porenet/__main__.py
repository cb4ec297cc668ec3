from porenet.cli.main import main

raise SystemExit(main())
