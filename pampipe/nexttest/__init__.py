"""`pampipe next-test`: the test of a lab's menu that lowers the planned pressure most per unit cost."""
